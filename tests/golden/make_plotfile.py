#!/usr/bin/env python3
"""Writes a tiny two-level AMReX plotfile (3D, cell-centred, float64 little endian) for the golden
image tests: usage make_plotfile.py DIR. Standard library only; output is byte-for-byte
deterministic. Layout as AMReX writes it (see src/volstream/io/plotfile.h)."""
import math
import os
import struct
import sys

COMPONENTS = ["density", "temp"]
PROB_LO = (0.0, 0.0, 0.0)
PROB_HI = (2.0, 2.0, 1.0)
L0 = ((0, 0, 0), (31, 31, 15))           # level-0 domain, inclusive
RATIO = 2
LEVELS = [
    [((0, 0, 0), (15, 15, 15)), ((16, 0, 0), (31, 15, 15)), ((0, 16, 0), (15, 31, 15)), ((16, 16, 0), (31, 31, 15))],
    [((16, 16, 8), (39, 39, 23)), ((40, 20, 10), (47, 35, 21))],
]


def value(c, level, i, j, k):
    # world coordinates of the cell centre
    n = (L0[1][0] + 1) * RATIO ** level, (L0[1][1] + 1) * RATIO ** level, (L0[1][2] + 1) * RATIO ** level
    x = PROB_LO[0] + (i + 0.5) * (PROB_HI[0] - PROB_LO[0]) / n[0]
    y = PROB_LO[1] + (j + 0.5) * (PROB_HI[1] - PROB_LO[1]) / n[1]
    z = PROB_LO[2] + (k + 0.5) * (PROB_HI[2] - PROB_LO[2]) / n[2]
    r2 = (x - 1.1) ** 2 + (y - 0.95) ** 2 + 2.0 * (z - 0.5) ** 2
    if c == 0:
        return math.exp(-6.0 * r2) + 0.15 * math.sin(4.0 * x) * math.cos(3.0 * y) + 0.2 + 0.01 * level
    return 300.0 + 5000.0 * math.exp(-3.0 * r2) + 40.0 * z


def vec(v):
    return "(%d,%d,%d)" % v


def box(b):
    return "(%s %s (0,0,0))" % (vec(b[0]), vec(b[1]))


def g(x):
    return repr(float(x)) if x != int(x) else str(int(x))


def main(out):
    os.makedirs(out, exist_ok=True)
    domains = [L0]
    for _ in LEVELS[1:]:
        lo, hi = domains[-1]
        domains.append((tuple(a * RATIO for a in lo), tuple((a + 1) * RATIO - 1 for a in hi)))
    for level, boxes in enumerate(LEVELS):
        ldir = os.path.join(out, "Level_%d" % level)
        os.makedirs(ldir, exist_ok=True)
        fabs = []
        for b, bx in enumerate(boxes):
            name = "Cell_D_%05d" % b
            (x0, y0, z0), (x1, y1, z1) = bx
            head = ("FAB ((8, (64 11 52 0 1 12 0 1023)),(8, (8 7 6 5 4 3 2 1)))%s %d\n" % (box(bx), len(COMPONENTS))).encode()
            data = bytearray(head)
            mins, maxs = [], []
            for c in range(len(COMPONENTS)):
                vals = [value(c, level, i, j, k) for k in range(z0, z1 + 1) for j in range(y0, y1 + 1) for i in range(x0, x1 + 1)]
                data += struct.pack("<%dd" % len(vals), *vals)
                mins.append(min(vals))
                maxs.append(max(vals))
            with open(os.path.join(ldir, name), "wb") as f:
                f.write(data)
            fabs.append((name, mins, maxs))
        h = ["1\n0\n%d\n0\n(%d 0\n" % (len(COMPONENTS), len(boxes))]
        h += [box(bx) + "\n" for bx in boxes]
        h.append(")\n%d\n" % len(fabs))
        h += ["FabOnDisk: %s 0\n" % f[0] for f in fabs]
        for which in (1, 2):
            h.append("\n%d,%d\n" % (len(fabs), len(COMPONENTS)))
            h += ["".join("%.16e," % v for v in f[which]) + "\n" for f in fabs]
        with open(os.path.join(ldir, "Cell_H"), "w") as f:
            f.write("".join(h))
    finest = len(LEVELS) - 1
    h = ["HyperCLaw-V1.1\n%d\n" % len(COMPONENTS)] + [c + "\n" for c in COMPONENTS]
    h.append("3\n0\n%d\n" % finest)
    h.append("".join(g(v) + " " for v in PROB_LO) + "\n")
    h.append("".join(g(v) + " " for v in PROB_HI) + "\n")
    h.append("".join("%d " % RATIO for _ in range(finest)) + "\n")
    h.append("".join(box(d) + " " for d in domains) + "\n")
    h.append("0 " * (finest + 1) + "\n")
    dx = []
    for d in domains:
        e = [d[1][a] - d[0][a] + 1 for a in range(3)]
        dx.append([(PROB_HI[a] - PROB_LO[a]) / e[a] for a in range(3)])
        h.append("".join(repr(v) + " " for v in dx[-1]) + "\n")
    h.append("0\n0\n")
    for level, boxes in enumerate(LEVELS):
        h.append("%d %d 0\n0\n" % (level, len(boxes)))
        for bx in boxes:
            for a in range(3):
                lo = PROB_LO[a] + (bx[0][a] - domains[level][0][a]) * dx[level][a]
                hi = PROB_LO[a] + (bx[1][a] + 1 - domains[level][0][a]) * dx[level][a]
                h.append("%r %r\n" % (lo, hi))
        h.append("Level_%d/Cell\n" % level)
    with open(os.path.join(out, "Header"), "w") as f:
        f.write("".join(h))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: make_plotfile.py DIR")
    main(sys.argv[1])
