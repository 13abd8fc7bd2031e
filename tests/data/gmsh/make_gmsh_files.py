#!/usr/bin/python3
"""Writes the Gmsh test files of tests/io/gmsh_test.cpp with Gmsh itself (Debian: apt-get install
gmsh python3-gmsh; run by developers, not by the tests): run it in this directory.

- gmsh_tets_41a.msh, _41b, _22a, _22b (MSH 4.1 and 2.2,
  ascii and binary): a box with a cylindrical hole (non-convex) in tets; node views f (linear),
  g (nonlinear, partly per node tag) and vel (3 components) at time steps 0, 1, 2 (times 0, 0.5,
  1.25), an element view pressure at the same steps and an element view cell_id given once.
- gmsh_mixed.msh (4.1 binary): hexes (a transfinite, recombined block), prisms (triangles
  extruded in layers) and, on top, tets with pyramids where they meet the hexes' quads; views
  f, g, cell_id.
- gmsh_serendipity.msh (4.1 ascii): that mesh of second order, incomplete (tet10, hex20,
  prism15, pyramid13), its mid-edge nodes moved off the edges (curved elements).
- gmsh_quadratic.msh (2.2 binary): the hex and prism blocks of second order, complete (hex27,
  prism18), curved likewise.
- gmsh_pyramid14.msh (4.1 ascii, no views): the mixed mesh of complete second order, whose
  14-node pyramids VTK lacks (refused).
- gmsh_groups_41.msh (4.1 ascii), _41b (4.1 binary), _41p (4.1 binary, partitioned in three:
  its elements on $PartitionedEntities) and gmsh_groups_22.msh (2.2 binary): the mixed mesh with
  physical groups of volumes that overlap (7 "hex block", 8 "prisms", 9 "top" of two volumes,
  11 "lower" of the hexes' and prisms' volumes, 12 without a name) and one of surfaces
  (5 "bottom"); views f and cell_id (each element's number in Gmsh's model: 2.2 numbers its
  elements anew, and writes an element once per group holding it). gmsh_groups.txt: per group,
  "number count sum" of its volume elements and of their cell_id, from Gmsh's model.

For each file but the last, FILE_probes.txt: points inside elements and the value of the view g
there, as Gmsh's own basis functions give it (gmsh.model.mesh.getBasisFunctions), so the node
orders volstream turns into VTK's are checked against Gmsh, not against the tables they were
derived from. A linear element is probed at random points of its reference element. A quadratic
element is split by volstream into the linear pieces of its nodes (umesh/quadratic.h: each edge
halved), where a field is exact only at the nodes, so it is probed inside the piece at each of its
corners (the reference element shrunk by half towards that corner, which is a piece of the split
for every type): the piece's corners are mapped and given values by the quadratic element's
basis (at nodes: the node and its value; at the face and body centres volstream adds for hex20,
prism15 and pyramid13: the shape functions' values there), and the point and value inside by the
linear element's basis. g's node values are not a smooth function of position (a term per node
tag), so a node put in the wrong place moves the piece's value, not just its shape.
"""
import math
import os
import random

import gmsh

random.seed(7)
PROBED_PER_TYPE = 12  # elements of each type probed
LINEAR = {4: 4, 5: 5, 6: 6, 7: 7, 11: 4, 17: 5, 12: 5, 18: 6, 13: 6, 19: 7, 14: 7}


def f_value(x, y, z, step):
    return (1 + step) * (x + 2 * y + 3 * z)


def g_value(tag, x, y, z, step):
    return math.sin(3 * x + step) + math.cos(2 * y) * z + 0.25 * ((tag * 7919) % 13) / 13


def nodes():
    tags, coords, _ = gmsh.model.mesh.getNodes()
    return [int(t) for t in tags], {int(t): tuple(coords[3 * i:3 * i + 3]) for i, t in enumerate(tags)}


def volume_elements():
    """(type, element tag, node tags) of every volume element, in Gmsh's node order."""
    out = []
    types, tags, node_tags = gmsh.model.mesh.getElements(3)
    for t, el, nt in zip(types, tags, node_tags):
        n = len(nt) // len(el)
        out += [(int(t), int(e), [int(x) for x in nt[i * n:(i + 1) * n]]) for i, e in enumerate(el)]
    return out


def add_views(steps, elements_view=True):
    """Node views f, g, vel and element views pressure (per step), cell_id (once)."""
    model = gmsh.model.getCurrent()
    tags, xyz = nodes()
    elements = volume_elements()
    views = []
    for name, fn, comps in [("f", lambda t, p, s: [f_value(*p, s)], 1),
                            ("g", lambda t, p, s: [g_value(t, *p, s)], 1),
                            ("vel", lambda t, p, s: [p[1] * (1 + s), -p[0], 0.5 * s], 3)]:
        v = gmsh.view.add(name)
        for s, time in steps:
            gmsh.view.addModelData(v, s, model, "NodeData", tags, [fn(t, xyz[t], s) for t in tags], time=time,
                                   numComponents=comps)
        views.append(v)
    if elements_view:
        v = gmsh.view.add("pressure")
        for s, time in steps:
            gmsh.view.addModelData(v, s, model, "ElementData", [e[1] for e in elements],
                                   [[e[1] * 0.5 + s] for e in elements], time=time, numComponents=1)
        views.append(v)
    v = gmsh.view.add("cell_id")
    gmsh.view.addModelData(v, 0, model, "ElementData", [e[1] for e in elements], [[float(e[1])] for e in elements],
                           time=0.0, numComponents=1)
    views.append(v)
    return views


def write(name, version, binary, views):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", binary)
    gmsh.option.setNumber("PostProcessing.SaveMesh", 1)
    gmsh.write(name)
    gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
    for v in views:
        gmsh.view.write(v, name, append=True)


def basis(etype, ref_points):
    """Gmsh's basis functions of `etype` at reference points: one list per point."""
    _, values, _ = gmsh.model.mesh.getBasisFunctions(etype, [c for p in ref_points for c in p], "Lagrange")
    n = len(values) // len(ref_points)
    return [values[i * n:(i + 1) * n] for i in range(len(ref_points))]


def reference_corners(linear_type):
    coords = gmsh.model.mesh.getElementProperties(linear_type)[4]
    return [tuple(coords[3 * i:3 * i + 3]) for i in range(len(coords) // 3)]


def random_inside(corners):
    """A random point strictly inside the convex hull of `corners`."""
    w = [random.uniform(0.2, 1.0) for _ in corners]
    s = sum(w)
    return tuple(sum(w[k] * corners[k][a] for k in range(len(corners))) / s for a in range(3))


def probes(name, g_of, quadratic):
    """FILE_probes.txt: "type x y z g" per probe (see the module's docstring)."""
    _, xyz = nodes()
    rows = []
    by_type = {}
    for e in volume_elements():
        by_type.setdefault(e[0], []).append(e)
    sample = [e for t in sorted(by_type) for e in random.sample(by_type[t], min(PROBED_PER_TYPE, len(by_type[t])))]
    for etype, _, element_nodes in sample:
        linear = LINEAR[etype]
        corners = reference_corners(linear)
        places = [xyz[n] for n in element_nodes]
        values = [g_of(n) for n in element_nodes]
        # The pieces probed: the element itself (linear), or its corners' halves (quadratic).
        pieces = [[tuple((c[a] + k[a]) / 2 for a in range(3)) for k in corners] for c in corners] if quadratic else [corners]
        for piece in pieces:
            weights = basis(etype, piece)  # the quadratic (or linear) element's basis at the piece's corners
            piece_xyz = [tuple(sum(w[i] * places[i][a] for i in range(len(w))) for a in range(3)) for w in weights]
            piece_g = [sum(w[i] * values[i] for i in range(len(w))) for w in weights]
            for _ in range(2 if quadratic else 3):
                inner = basis(linear, [random_inside(corners)])[0]
                p = [sum(inner[k] * piece_xyz[k][a] for k in range(len(inner))) for a in range(3)]
                rows.append((etype, *p, sum(inner[k] * piece_g[k] for k in range(len(inner)))))
    with open(name, "w") as out:
        out.write("# Gmsh element type, x, y, z, the view g (step 0) there by Gmsh's basis functions\n")
        for r in rows:
            out.write("%d %.17g %.17g %.17g %.17g\n" % r)


def curve_high_order_nodes(amount):
    """Moves every node that is not an element corner by up to `amount` in each axis."""
    corners = set()
    for etype, _, element_nodes in volume_elements():
        corners.update(element_nodes[:len(reference_corners(LINEAR[etype]))])
    tags, xyz = nodes()
    for t in tags:
        if t not in corners:
            p = [c + random.uniform(-amount, amount) for c in xyz[t]]
            gmsh.model.mesh.setNode(t, p, [])


def tets():
    gmsh.model.add("tets")
    box = gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
    hole = gmsh.model.occ.addCylinder(1, 0.5, -0.1, 0, 0, 1.2, 0.3)
    gmsh.model.occ.cut([(3, box)], [(3, hole)])
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.6)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.9)
    gmsh.model.mesh.generate(3)
    views = add_views([(0, 0.0), (1, 0.5), (2, 1.25)])
    for suffix, version, binary in [("41a", 4.1, 0), ("41b", 4.1, 1), ("22a", 2.2, 0), ("22b", 2.2, 1)]:
        write("gmsh_tets_" + suffix + ".msh", version, binary, views)
    tags, xyz = nodes()
    probes("gmsh_tets_probes.txt", lambda n: g_value(n, *xyz[n], 0), False)
    for v in views:
        gmsh.view.remove(v)
    gmsh.model.remove()


def mixed_blocks(with_top):
    """Hexes in [0,1]x[0,1]x[0,1], prisms in [1,2]x[0,1]x[0,1] and, `with_top`, tets (and
    pyramids on the hexes' quads) in [0,2]x[0,1]x[1,1.6]."""
    geo = gmsh.model.geo
    p = [geo.addPoint(x, y, 0) for x, y in [(0, 0), (1, 0), (1, 1), (0, 1), (2, 0), (2, 1)]]
    l = [geo.addLine(p[0], p[1]), geo.addLine(p[1], p[2]), geo.addLine(p[2], p[3]), geo.addLine(p[3], p[0]),
         geo.addLine(p[1], p[4]), geo.addLine(p[4], p[5]), geo.addLine(p[5], p[2])]
    left = geo.addPlaneSurface([geo.addCurveLoop([l[0], l[1], l[2], l[3]])])
    right = geo.addPlaneSurface([geo.addCurveLoop([l[4], l[5], l[6], -l[1]])])
    for c in l[:4]:
        geo.mesh.setTransfiniteCurve(c, 3)
    geo.mesh.setTransfiniteSurface(left)
    geo.mesh.setRecombine(2, left)
    hexes = geo.extrude([(2, left)], 0, 0, 1, numElements=[2], recombine=True)
    prisms = geo.extrude([(2, right)], 0, 0, 1, numElements=[2], recombine=True)
    if with_top:
        geo.extrude([(2, hexes[0][1]), (2, prisms[0][1])], 0, 0, 0.6)
    geo.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.7)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.9)
    gmsh.model.mesh.generate(3)


def mixed():
    gmsh.model.add("mixed")
    mixed_blocks(True)
    views = add_views([(0, 0.0)], elements_view=False)
    write("gmsh_mixed.msh", 4.1, 1, views)
    tags, xyz = nodes()
    probes("gmsh_mixed_probes.txt", lambda n: g_value(n, *xyz[n], 0), False)
    gmsh.model.remove()


def groups():
    gmsh.model.add("groups")
    mixed_blocks(True)
    volumes = [tag for _, tag in gmsh.model.getEntities(3)]
    assert volumes == [1, 2, 3, 4], volumes
    for dim, entities, number, name in [(3, [1], 7, "hex block"), (3, [2], 8, "prisms"), (3, [3, 4], 9, "top"),
                                        (3, [1, 2], 11, "lower"), (3, [4], 12, None), (2, [1], 5, "bottom")]:
        gmsh.model.addPhysicalGroup(dim, entities, number)
        if name:
            gmsh.model.setPhysicalName(dim, number, name)
    views = add_views([(0, 0.0)], elements_view=False)
    views = [v for v in views if gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(v)) in ("f", "cell_id")]
    write("gmsh_groups_41.msh", 4.1, 0, views)
    write("gmsh_groups_41b.msh", 4.1, 1, views)
    write("gmsh_groups_22.msh", 2.2, 1, views)
    gmsh.model.mesh.partition(3)  # after the counts below: they are the model's, not the partitions'
    write("gmsh_groups_41p.msh", 4.1, 1, views)
    gmsh.model.mesh.unpartition()
    with open("gmsh_groups.txt", "w") as out:
        out.write("# physical group of volumes, its volume elements, the sum of their numbers (cell_id)\n")
        for _, number in gmsh.model.getPhysicalGroups(3):
            tags = []
            for entity in gmsh.model.getEntitiesForPhysicalGroup(3, number):
                for el in gmsh.model.mesh.getElements(3, entity)[1]:
                    tags += [int(t) for t in el]
            out.write("%d %d %d\n" % (number, len(tags), sum(tags)))
    gmsh.model.remove()


def second_order(name, with_top, incomplete, version, binary, curve, with_probes=True):
    gmsh.model.add(name)
    mixed_blocks(with_top)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", incomplete)
    gmsh.model.mesh.setOrder(2)
    curve_high_order_nodes(curve)
    tags, xyz = nodes()
    views = add_views([(0, 0.0)], elements_view=False) if with_probes else []
    write(name + ".msh", version, binary, views)
    if with_probes:
        probes(name + "_probes.txt", lambda n: g_value(n, *xyz[n], 0), True)
    gmsh.model.remove()


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
tets()
mixed()
groups()
# The pyramids are flat (their apexes low in the thin top layer): moved nodes 0.03 away tangle
# their pieces.
second_order("gmsh_serendipity", True, 1, 4.1, 0, 0.02)
second_order("gmsh_quadratic", False, 0, 2.2, 1, 0.04)
second_order("gmsh_pyramid14", True, 0, 4.1, 0, 0.0, with_probes=False)
gmsh.finalize()
for name in sorted(os.listdir(".")):
    if name.startswith("gmsh_"):
        print(name, os.path.getsize(name))
