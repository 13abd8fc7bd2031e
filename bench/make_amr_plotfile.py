#!/usr/bin/env python3
"""Writes the CPU-speed benchmark's AMReX plotfile (bench/cpu_speed.sh): 3 levels, ratio 2,
720,896 leaf cells, one float64 field `density` spanning about four decades, boxes of at most
32^3 cells (AMReX's usual max_grid_size). usage: make_amr_plotfile.py DIR

Level 0 is 64^3 over [0,1]^3; level 1 refines its central 32^3 cells (a 64^3 box of level-1
cells), level 2 the central 32^3 of those (a 64^3 box of level-2 cells). Leaf cells:
64^3 - 32^3 + 64^3 - 32^3 + 64^3 = 720,896. Layout as tests/golden/make_plotfile.py and
vs::write_plotfile (src/volstream/io/plotfile.h) write it; numpy for speed."""
import os
import sys

import numpy as np

N0 = 64
MAX_GRID = 32
# Per level: the refined box in that level's index space, inclusive.
LEVEL_BOXES = [((0, 0, 0), (63, 63, 63)), ((32, 32, 32), (95, 95, 95)), ((96, 96, 96), (159, 159, 159))]


def density(x, y, z):
    """A bright core, two off-centre blobs and a faint rippled background: log10 from about -3.3
    to 0.7, so that layers across the log range meet structure at every level."""
    r2 = (x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2
    b1 = (x - 0.42) ** 2 + (y - 0.56) ** 2 + (z - 0.47) ** 2
    b2 = (x - 0.3) ** 2 + (y - 0.25) ** 2 + (z - 0.7) ** 2
    ripple = 1.0 + 0.5 * np.sin(23.0 * x) * np.cos(17.0 * y) * np.sin(19.0 * z)
    return 1e-3 * ripple + 4.0 * np.exp(-r2 / 0.004) + 0.5 * np.exp(-b1 / 0.0008) + 0.05 * np.exp(-b2 / 0.01) + 1e-4


def split(lo, hi):
    """The box cut into boxes of at most MAX_GRID cells per axis."""
    out = []
    for k in range(lo[2], hi[2] + 1, MAX_GRID):
        for j in range(lo[1], hi[1] + 1, MAX_GRID):
            for i in range(lo[0], hi[0] + 1, MAX_GRID):
                out.append(((i, j, k), (min(i + MAX_GRID - 1, hi[0]), min(j + MAX_GRID - 1, hi[1]),
                                        min(k + MAX_GRID - 1, hi[2]))))
    return out


def box_text(b):
    return "((%d,%d,%d) (%d,%d,%d) (0,0,0))" % (*b[0], *b[1])


def write(out):
    os.makedirs(out, exist_ok=True)
    finest = len(LEVEL_BOXES) - 1
    domains = [((0, 0, 0), tuple(N0 * 2**lev - 1 for _ in range(3))) for lev in range(finest + 1)]
    for level, region in enumerate(LEVEL_BOXES):
        ldir = os.path.join(out, "Level_%d" % level)
        os.makedirs(ldir, exist_ok=True)
        dx = 1.0 / (N0 * 2**level)
        boxes = split(*region)
        fabs = []
        for b, (lo, hi) in enumerate(boxes):
            i = (np.arange(lo[0], hi[0] + 1) + 0.5) * dx
            j = (np.arange(lo[1], hi[1] + 1) + 0.5) * dx
            k = (np.arange(lo[2], hi[2] + 1) + 0.5) * dx
            z, y, x = np.meshgrid(k, j, i, indexing="ij")  # x fastest, as FABs store them
            v = density(x, y, z).astype("<f8")
            name = "Cell_D_%05d" % b
            with open(os.path.join(ldir, name), "wb") as f:
                f.write(("FAB ((8, (64 11 52 0 1 12 0 1023)),(8, (8 7 6 5 4 3 2 1)))%s 1\n" %
                         box_text((lo, hi))).encode())
                f.write(v.tobytes())
            fabs.append((name, float(v.min()), float(v.max())))
        h = ["1\n0\n1\n0\n(%d 0\n" % len(boxes)] + [box_text(bx) + "\n" for bx in boxes]
        h.append(")\n%d\n" % len(fabs))
        h += ["FabOnDisk: %s 0\n" % f[0] for f in fabs]
        for which in (1, 2):
            h.append("\n%d,1\n" % len(fabs))
            h += ["%.16e,\n" % f[which] for f in fabs]
        with open(os.path.join(ldir, "Cell_H"), "w") as f:
            f.write("".join(h))
    h = ["HyperCLaw-V1.1\n1\ndensity\n3\n0\n%d\n" % finest, "0 0 0 \n", "1 1 1 \n"]
    h.append("2 " * finest + "\n")
    h.append("".join(box_text(d) + " " for d in domains) + "\n")
    h.append("0 " * (finest + 1) + "\n")
    for level in range(finest + 1):
        h.append(("%r " % (1.0 / (N0 * 2**level))) * 3 + "\n")
    h.append("0\n0\n")
    for level, region in enumerate(LEVEL_BOXES):
        boxes = split(*region)
        dx = 1.0 / (N0 * 2**level)
        h.append("%d %d 0\n0\n" % (level, len(boxes)))
        for lo, hi in boxes:
            for a in range(3):
                h.append("%r %r\n" % (lo[a] * dx, (hi[a] + 1) * dx))
        h.append("Level_%d/Cell\n" % level)
    with open(os.path.join(out, "Header"), "w") as f:
        f.write("".join(h))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: make_amr_plotfile.py DIR")
    write(sys.argv[1])
