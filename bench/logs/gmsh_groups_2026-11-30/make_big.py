# The Gmsh bench meshes of this directory: a box of about 1M tets (mesh size H, 0.018 gave
# 793,497) in four volumes (2x2 columns), a node view f = x + 2y + 3z. Run with Debian's
# python3-gmsh: /usr/bin/python3 make_big.py H VARIANT, VARIANT one of
#   overlapping: a physical group per volume (part0..part3) and "all" of the four, written as
#                big41.msh (MSH 4.1 binary) and big22.msh (MSH 2.2 binary: each element twice);
#   single:      the groups per volume only, big22single.msh (2.2: each element once);
#   saveall:     no groups, Mesh.SaveAll, big22all.msh (2.2).
import sys
import gmsh

h, variant = float(sys.argv[1]), sys.argv[2]
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
if variant == "saveall":
    gmsh.option.setNumber("Mesh.SaveAll", 1)
gmsh.model.add("big")
occ = gmsh.model.occ
vols = [occ.addBox(i * 0.5, j * 0.5, 0, 0.5, 0.5, 1) for i in range(2) for j in range(2)]
occ.fragment([(3, vols[0])], [(3, v) for v in vols[1:]])
occ.synchronize()
gmsh.option.setNumber("Mesh.MeshSizeMin", h)
gmsh.option.setNumber("Mesh.MeshSizeMax", h)
gmsh.model.mesh.generate(3)
vs = [t for _, t in gmsh.model.getEntities(3)]
if variant != "saveall":
    for k, v in enumerate(vs):
        gmsh.model.addPhysicalGroup(3, [v], k + 1)
        gmsh.model.setPhysicalName(3, k + 1, "part%d" % k)
if variant == "overlapping":
    gmsh.model.addPhysicalGroup(3, vs, 100)
    gmsh.model.setPhysicalName(3, 100, "all")
tags, coords, _ = gmsh.model.mesh.getNodes()
v = gmsh.view.add("f")
gmsh.view.addModelData(v, 0, "big", "NodeData", tags,
                       [[coords[3 * i] + 2 * coords[3 * i + 1] + 3 * coords[3 * i + 2]] for i in range(len(tags))],
                       numComponents=1)
files = {"overlapping": [("big41.msh", 4.1), ("big22.msh", 2.2)], "single": [("big22single.msh", 2.2)],
         "saveall": [("big22all.msh", 2.2)]}[variant]
for name, version in files:
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.option.setNumber("PostProcessing.SaveMesh", 1)
    gmsh.write(name)
    gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
    gmsh.view.write(v, name, append=True)
print(sum(len(e) for e in gmsh.model.mesh.getElements(3)[1]))
gmsh.finalize()
