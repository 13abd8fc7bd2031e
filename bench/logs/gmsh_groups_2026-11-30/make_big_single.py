# A box of about 1M tets in four volumes (2x2 columns), overlapping groups: one per volume and
# "all"; a node view f; written as MSH 4.1 binary and 2.2 binary (each element twice in 2.2).
import sys
import gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("big")
occ = gmsh.model.occ
vols = [occ.addBox(i * 0.5, j * 0.5, 0, 0.5, 0.5, 1) for i in range(2) for j in range(2)]
occ.fragment([(3, vols[0])], [(3, v) for v in vols[1:]])
occ.synchronize()
h = float(sys.argv[1]) if len(sys.argv) > 1 else 0.02
gmsh.option.setNumber("Mesh.MeshSizeMin", h)
gmsh.option.setNumber("Mesh.MeshSizeMax", h)
gmsh.model.mesh.generate(3)
vs = [t for _, t in gmsh.model.getEntities(3)]
for k, v in enumerate(vs):
    gmsh.model.addPhysicalGroup(3, [v], k + 1)
    gmsh.model.setPhysicalName(3, k + 1, "part%d" % k)
pass
pass
tags, coords, _ = gmsh.model.mesh.getNodes()
v = gmsh.view.add("f")
gmsh.view.addModelData(v, 0, "big", "NodeData", tags, [[coords[3*i] + 2*coords[3*i+1] + 3*coords[3*i+2]] for i in range(len(tags))], numComponents=1)
for name, ver in [("big22single.msh", 2.2)]:
    gmsh.option.setNumber("Mesh.MshFileVersion", ver)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.option.setNumber("PostProcessing.SaveMesh", 1)
    gmsh.write(name)
    gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
    gmsh.view.write(v, name, append=True)
print(sum(len(e) for e in gmsh.model.mesh.getElements(3)[1]))
gmsh.finalize()
