#!/usr/bin/python3
"""Writes a Fluent case of N^3 hexes over the unit cube and STEPS data files, for the convert
benchmarks of Fluent's files at the size of real runs (the test files are a few hundred cells).
The layout and section formats are the test writer's (tests/data/fluent/make_fluent_files.py,
checked there against VTK's vtkFLUENTReader), in binary: float64 nodes (3010), one hex cell zone
(12, element type 4), an interior and a wall face zone of quads (2013, mixed rows: node count,
nodes, c0, c1; each face's right-hand normal into c0), and per step float64 cell data (3300):
pressure and temperature, smooth functions of the cell centre times (1 + S/10), flow time S.

usage: /usr/bin/python3 bench/fluent_box.py N OUT_STEM [STEPS=8]
       writes OUT_STEM.cas and OUT_STEM-S.dat for S = 0 .. STEPS-1
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "fluent"))
import make_fluent_files as fl  # noqa: E402

# A face's four corners (offsets in nodes), in the order whose right-hand normal is +axis.
CORNERS = {0: [(0, 0, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)],
           1: [(0, 0, 0), (0, 0, 1), (1, 0, 1), (1, 0, 0)],
           2: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]}


def faces(n):
    """(interior rows, wall rows): int32 arrays of [4, n0, n1, n2, n3, c0, c1], 1-based."""
    node = lambda i, j, k: 1 + i + (n + 1) * (j + (n + 1) * k)
    cell = lambda i, j, k: 1 + i + n * (j + n * k)
    interior, wall = [], []
    for axis in range(3):
        # planes p = 0..n across `axis`; a, b the face's place in the other two axes
        p, a, b = np.meshgrid(np.arange(n + 1), np.arange(n), np.arange(n), indexing="ij")
        ijk = [None, None, None]
        ijk[axis], ijk[(axis + 1) % 3], ijk[(axis + 2) % 3] = p, a, b
        corners = []
        for offset in CORNERS[axis]:
            corners.append(node(*(ijk[d] + offset[d] for d in range(3))))
        before = [ijk[d] - (1 if d == axis else 0) for d in range(3)]
        rows = np.stack([np.full(p.shape, 4)] + corners +
                        [cell(*np.minimum(ijk, n - 1)), cell(*np.maximum(before, 0))], axis=-1)
        rows = rows.reshape(n + 1, n * n, 7)
        inner = rows[1:n].reshape(-1, 7)  # c0 the cell after the plane (the normal's), c1 the one before
        low = rows[0].copy()
        low[:, 6] = 0
        high = rows[n].copy()  # the cell before is the only one: its corners turned to face into it
        high[:, 1:5] = high[:, 4:0:-1]
        high[:, 5], high[:, 6] = high[:, 6], 0
        interior.append(inner)
        wall += [low, high]
    return np.concatenate(interior).astype(np.int32), np.concatenate(wall).astype(np.int32)


def write_case(n, name):
    g = np.linspace(0.0, 1.0, n + 1)
    z, y, x = np.meshgrid(g, g, g, indexing="ij")
    xyz = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    interior, wall = faces(n)
    n_nodes, n_cells, n_faces = len(xyz), n ** 3, len(interior) + len(wall)
    out = [b'(0 "volstream bench: fluent_box.py")\n', b"(2 3)\n", f"(10 (0 1 {n_nodes:x} 0 3))\n".encode(),
           f"(12 (0 1 {n_cells:x} 0))\n".encode(), f"(13 (0 1 {n_faces:x} 0))\n".encode(),
           fl.binary_section(3010, f"{fl.NODE_ZONE:x} 1 {n_nodes:x} 1 3", xyz.astype("<f8").tobytes()),
           f"(12 (2 1 {n_cells:x} 1 4))\n".encode()]
    first = 1
    for zone, bc, rows in ((fl.INTERIOR_ZONE, fl.INTERIOR, interior), (fl.WALL_ZONE, fl.WALL, wall)):
        header = f"{zone:x} {first:x} {first + len(rows) - 1:x} {bc:x} 0"
        out.append(fl.binary_section(2013, header, rows.astype("<i4").tobytes()))
        first += len(rows)
    out += [b'(0 "zones")\n', b"(39 (2 fluid fluid 1)())\n",
            f"(39 ({fl.INTERIOR_ZONE} interior default-interior 1)())\n".encode(),
            f"(45 ({fl.WALL_ZONE} wall walls)())\n".encode()]
    with open(name, "wb") as f:
        f.write(b"".join(out))
    return n_cells, n_faces, len(xyz)


def write_data(n, name, step, n_faces, n_nodes):
    c = (np.arange(n) + 0.5) / n
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    scale = 1 + step / 10
    values = {fl.SV_P: (np.exp(-8 * ((x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.45) ** 2)) * scale).ravel(),
              fl.SV_T: (300 + x + 2 * y + 3 * z * scale).ravel()}
    out = [b'(0 "volstream bench data")\n', f"(37 (\n(flow-time {float(step)!r})\n))\n".encode(),
           f"(33 ({n ** 3} {n_faces} {n_nodes}))\n".encode()]
    for sv, v in values.items():
        out.append(fl.binary_section(3300, f"{sv} 2 1 0 0 1 {n ** 3}", v.astype("<f8").tobytes()))
    with open(name, "wb") as f:
        f.write(b"".join(out))


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    n, stem = int(sys.argv[1]), sys.argv[2]
    steps = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    cells, n_faces, n_nodes = write_case(n, stem + ".cas")
    for s in range(steps):
        write_data(n, f"{stem}-{s}.dat", s, n_faces, n_nodes)
    print(f"{stem}.cas: {cells} hexes, {n_faces} faces, {n_nodes} nodes; {steps} data files")
