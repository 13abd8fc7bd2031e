#!/usr/bin/python3
"""Compare two 8-bit PNGs (RGB or RGBA, same size): RMSE and more, optionally a difference image.

usage: png_compare.py A.png B.png [--diff DIFF.png] [--gain 4] [--json]

Prints, over the RGB channels in 8-bit units (alpha is ignored):
  rmse            root mean square difference over every pixel and channel
  rmse_covered    the same over the pixels where A or B differs from its corner pixel (the
                  background) by more than 2 in some channel: the picture without the empty border
  max             largest channel difference
  over8, over32   fraction of pixels with some channel differing by more than 8 (32)
  mean_a, mean_b  mean channel value (a brightness bias shows as a difference of these)
--diff writes |A - B| * gain per channel (an RGB PNG). Pure Python (zlib, struct); numpy is used
when it is installed, only for speed.
"""
import argparse
import json
import struct
import sys
import zlib


def read_png(path):
    """Returns (width, height, channels, rows): rows a list of bytes, top row first."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, hdr = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        tag = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if tag == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif tag == b"IDAT":
            idat.append(body)
        elif tag == b"IEND":
            break
    w, h, depth, ctype, _, _, interlace = hdr
    if depth != 8 or ctype not in (2, 6) or interlace:
        sys.exit(f"{path}: only 8-bit RGB/RGBA non-interlaced PNGs (depth {depth}, colour type {ctype})")
    ch = 3 if ctype == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = w * ch
    rows, prev = [], bytearray(stride)
    for y in range(h):
        ftype = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ftype == 1:
            for i in range(ch, stride):
                line[i] = (line[i] + line[i - ch]) & 255
        elif ftype == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif ftype == 3:
            for i in range(stride):
                left = line[i - ch] if i >= ch else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif ftype == 4:
            for i in range(stride):
                a = line[i - ch] if i >= ch else 0
                b = prev[i]
                c = prev[i - ch] if i >= ch else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if (pa <= pb and pa <= pc) else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        elif ftype != 0:
            sys.exit(f"{path}: bad filter type {ftype}")
        rows.append(bytes(line))
        prev = line
    return w, h, ch, rows


def rgb_pixels(w, h, ch, rows):
    """Flat list-like bytes of RGB triples, top row first."""
    if ch == 3:
        return b"".join(rows)
    out = bytearray(3 * w * h)
    k = 0
    for row in rows:
        for x in range(w):
            out[k:k + 3] = row[4 * x:4 * x + 3]
            k += 3
    return bytes(out)


def compare(a, b, w, h):
    bg_a, bg_b = a[0:3], b[0:3]
    n = w * h
    try:
        import numpy as np

        A = np.frombuffer(a, dtype=np.uint8).reshape(n, 3).astype(np.int32)
        B = np.frombuffer(b, dtype=np.uint8).reshape(n, 3).astype(np.int32)
        d = np.abs(A - B)
        cov = (np.abs(A - A[0]).max(1) > 2) | (np.abs(B - B[0]).max(1) > 2)
        dm = d.max(1)
        r = {
            "rmse": float(np.sqrt((d.astype(np.float64) ** 2).mean())),
            "rmse_covered": float(np.sqrt((d[cov].astype(np.float64) ** 2).mean())) if cov.any() else 0.0,
            "covered": float(cov.mean()),
            "max": int(d.max()),
            "over8": float((dm > 8).mean()),
            "over32": float((dm > 32).mean()),
            "mean_a": float(A.mean()),
            "mean_b": float(B.mean()),
        }
        return r, d.astype(np.uint8).tobytes()
    except ImportError:
        pass
    sq = sq_cov = 0
    ncov = over8 = over32 = dmax = suma = sumb = 0
    diff = bytearray(3 * n)
    for i in range(n):
        p = 3 * i
        m = 0
        s = 0
        cov = False
        for c in range(3):
            x, y = a[p + c], b[p + c]
            dd = abs(x - y)
            diff[p + c] = dd
            s += dd * dd
            m = max(m, dd)
            suma += x
            sumb += y
            if abs(x - bg_a[c]) > 2 or abs(y - bg_b[c]) > 2:
                cov = True
        sq += s
        dmax = max(dmax, m)
        over8 += m > 8
        over32 += m > 32
        if cov:
            ncov += 1
            sq_cov += s
    r = {
        "rmse": (sq / (3 * n)) ** 0.5,
        "rmse_covered": (sq_cov / (3 * ncov)) ** 0.5 if ncov else 0.0,
        "covered": ncov / n,
        "max": dmax,
        "over8": over8 / n,
        "over32": over32 / n,
        "mean_a": suma / (3 * n),
        "mean_b": sumb / (3 * n),
    }
    return r, bytes(diff)


def write_png(path, w, h, rgb):
    raw = b"".join(b"\x00" + rgb[3 * w * y:3 * w * (y + 1)] for y in range(h))

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--diff", help="write |A - B| * gain as a PNG")
    ap.add_argument("--gain", type=float, default=4.0)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    wa, ha, ca, ra = read_png(args.a)
    wb, hb, cb, rb = read_png(args.b)
    if (wa, ha) != (wb, hb):
        sys.exit(f"sizes differ: {wa}x{ha} vs {wb}x{hb}")
    r, diff = compare(rgb_pixels(wa, ha, ca, ra), rgb_pixels(wb, hb, cb, rb), wa, ha)
    if args.diff:
        write_png(args.diff, wa, ha, bytes(min(255, int(d * args.gain)) for d in diff))
    if args.json:
        print(json.dumps(r))
    else:
        print(" ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in r.items()))


if __name__ == "__main__":
    main()
