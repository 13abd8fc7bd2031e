#!/usr/bin/env python3
"""Helpers for tests/mpi/render_ranks.sh and bench/mpi_ranks.sh (standard library only).
  cameras INFO_JSON N SEED   N random cameras (half inside the domain, half outside) as
                             "--camera-pos x,y,z --camera-at x,y,z" lines
  compare A.pfm B.pfm TOL    max |a - b| over the PFM floats; exit 1 above TOL
  ranks LOG FIELDS CELLS     checks a mpirun render's per-rank lines: the regions' cells (a
                             mesh's elements) sum to CELLS and each rank read FIELDS * 4 bytes per
                             held cell (a mesh's held vertex); prints the ghost overhead
  topology LOG WHOLE         checks that each rank of a mpirun render read less than WHOLE bytes
                             of topology files (its share of a mesh or AMR); prints the most a rank read"""
import json
import random
import re
import struct
import sys


def cameras(info_path, n, seed):
    info = json.load(open(info_path))
    box = info["domain"]
    lo, hi = box["lower"], box["upper"]
    rng = random.Random(seed)
    for i in range(n):
        at = [l + rng.uniform(0.3, 0.7) * (h - l) for l, h in zip(lo, hi)]
        if i % 2 == 0:  # inside the domain
            pos = [l + rng.uniform(0.1, 0.9) * (h - l) for l, h in zip(lo, hi)]
        else:  # outside, on a random side
            pos = [l + rng.uniform(-1.0, 2.0) * (h - l) for l, h in zip(lo, hi)]
            a = rng.randrange(3)
            pos[a] = hi[a] + 0.8 * (hi[a] - lo[a]) if rng.random() < 0.5 else lo[a] - 0.8 * (hi[a] - lo[a])
        print("--camera-pos %s --camera-at %s" % (",".join("%.6g" % v for v in pos), ",".join("%.6g" % v for v in at)))


def read_pfm(path):
    data = open(path, "rb").read()
    parts = data.split(b"\n", 3)
    w, h = map(int, parts[1].split())
    scale = float(parts[2])
    fmt = "<" if scale < 0 else ">"
    channels = 3 if parts[0] == b"PF" else 1
    return struct.unpack(fmt + "%df" % (w * h * channels), parts[3][: 4 * w * h * channels])


def compare(a, b, tol):
    x, y = read_pfm(a), read_pfm(b)
    if len(x) != len(y):
        print("size differs")
        sys.exit(1)
    diff = max(abs(p - q) for p, q in zip(x, y))
    print("%.3g" % diff)
    sys.exit(0 if diff <= tol else 1)


def ranks(log, fields, cells):
    owned = held = 0
    for line in open(log):
        m = re.match(r"rank \d+: (cells|elements) (\d+) owned, (\d+) held \((\d+) .*values read (\d+) B", line)
        if not m:
            continue
        o, h, parts, r = map(int, m.groups()[1:])
        values = parts if m.group(1) == "elements" else h  # a mesh's values are per held vertex
        if r != fields * 4 * values:
            print("rank read %d B for %d held values" % (r, values))
            sys.exit(1)
        owned += o
        held += h
    if owned != cells:
        print("regions hold %d cells, the dataset %d" % (owned, cells))
        sys.exit(1)
    print("ghost overhead %+.1f%%" % (100.0 * (held / cells - 1)))


def topology(log, whole):
    read = [int(m.group(1)) for m in re.finditer(r"^rank \d+: .*topology read (\d+) B", open(log).read(), re.M)]
    if not read or max(read) >= whole:
        print("ranks read %s B of topology, the whole files are %d B" % (read, whole))
        sys.exit(1)
    print("ranks read %d to %d B of topology (whole: %d B)" % (min(read), max(read), whole))


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "cameras":
        cameras(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    elif cmd == "compare":
        compare(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    elif cmd == "ranks":
        ranks(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    elif cmd == "topology":
        topology(sys.argv[2], int(sys.argv[3]))
