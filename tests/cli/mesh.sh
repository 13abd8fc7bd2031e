#!/usr/bin/env bash
# Unstructured meshes end to end: demo meshes written as .vtu, legacy .vtk and UGRID (ascii and
# binary) convert to datasets that probe the same values; probe equals --brute-force at 10^4
# random points on the tet, mixed and non-convex demos; info, render and play work; a .pvd
# time series converts; bad mesh input is one line and exit 2; the compact encoding (the default)
# probes and renders what the reference one does, and refuses reference-only requests.
source "$(dirname "$0")/common.bash"
DATA="$(cd "$(dirname "$0")/../data/vtu" && pwd)"
cd "$WORK"

for demo in tets mixed holes; do
  "$VS" demo $demo --elements 4000 --steps 1 -o $demo -q
  random_points $demo 10000 3 >pts_$demo.txt
  "$VS" probe $demo --field density --points pts_$demo.txt >bvh.txt
  "$VS" probe $demo --field density --points pts_$demo.txt --brute-force >ref.txt
  echo -n "$demo: "
  compare_probes bvh.txt ref.txt || fail "$demo: BVH probe differs from brute force"
  grep -qv nan bvh.txt || fail "$demo: every probe is outside the mesh"
done

# Every file format the demo writes converts to the same values (UGRID has no data: the linear
# field comes back through --scalars from a raw float32 file).
# m.pvtu is four .vtu pieces with ghost cells, as a parallel writer's: joined at convert.
"$VS" demo mixed --elements 4000 --steps 1 -o ref -q --write-mesh m.vtu --write-mesh m.vtk \
  --write-mesh m.lb8.ugrid --write-mesh m.b8.ugrid --write-mesh m.ugrid --write-mesh m.pvtu
"$VS" probe ref --field linear --points pts_mixed.txt >expected.txt
for f in m.vtu m.vtk m.pvtu; do
  "$VS" convert $f -o conv_$f -q
  "$VS" probe conv_$f --field linear --points pts_mixed.txt >got.txt
  echo -n "$f: "
  compare_probes got.txt expected.txt || fail "$f differs from the demo dataset"
done
# The linear field x + 2y + 3z at the UGRID file's nodes, as raw float32 (the --scalars input).
/usr/bin/python3 - <<'PY'
import struct
data = open("m.lb8.ugrid", "rb").read()
counts = struct.unpack_from("<7i", data, 0)
xyz = struct.unpack_from("<%dd" % (3 * counts[0]), data, 28)
with open("linear.f32", "wb") as out:
    for i in range(counts[0]):
        out.write(struct.pack("<f", xyz[3 * i] + 2 * xyz[3 * i + 1] + 3 * xyz[3 * i + 2]))
PY
for f in m.lb8.ugrid m.b8.ugrid m.ugrid; do
  "$VS" convert $f -o conv_$f -q --scalars linear=linear.f32
  "$VS" probe conv_$f --field linear --points pts_mixed.txt >got.txt
  echo -n "$f: "
  compare_probes got.txt expected.txt || fail "$f differs from the demo dataset"
done
head -c 100 linear.f32 >short.f32
expect_bad_input "raw scalars of the wrong size" convert m.lb8.ugrid --scalars linear=short.f32 -o bad0
"$VS" info conv_m.vtu | grep -q "bytes_per_element" || fail "info shows no bytes_per_element"
"$VS" info conv_m.vtu --json | grep -q '"wedge"' || fail "info --json has no element counts by type"
# Split into tets at convert: the linear field is still exact (a point near the boundary, where
# the split cuts a curved face in two flat triangles, may lie in one mesh only: 9 of 10^4 here),
# info says what the source held, render works; AMR input refuses the flag.
"$VS" convert m.vtu -o split -q --split-into-tets --encoding reference
"$VS" probe split --field linear --points pts_mixed.txt >got.txt
echo -n "split into tets: "
compare_probes got.txt expected.txt 30 || fail "the mesh split into tets probes another linear field"
"$VS" info split | grep -q "split into tets at convert, from" || fail "info does not say the mesh was split"
"$VS" info split --json | grep -q '"split_from"' || fail "info --json has no split_from"
"$VS" render split -o split.png --size 64x64 >/dev/null || fail "render of a mesh split into tets failed"
"$VS" demo mixed --elements 2000 --steps 1 -o split_demo -q --split-into-tets
grep -q '"split_from"' split_demo/manifest.json || fail "demo --split-into-tets stored no split_from"
head -c 256 /dev/zero >grid.raw
expect_bad_input "--split-into-tets of AMR input" convert grid.raw --dims 4,4,4 --type float32 --split-into-tets -o bad_s

# Render, play, and a .pvd time series of three steps over one mesh.
"$VS" render holes -o holes.png --size 64x64 >render.txt || fail "render of a mesh failed"
"$VS" demo tets --elements 2000 --steps 3 -o series -q
"$VS" play series --size 48x48 -o "frame_%02d.png" >/dev/null || fail "play of a mesh failed"
for s in 0 1 2; do "$VS" demo tets --elements 2000 --steps 1 -o tmp_$s -q --write-mesh s$s.vtu; done
printf '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n' >series.pvd
for s in 0 1 2; do echo "<DataSet timestep=\"$s.5\" part=\"0\" file=\"s$s.vtu\"/>" >>series.pvd; done
printf '</Collection>\n</VTKFile>\n' >>series.pvd
"$VS" convert series.pvd -o pvd -q
"$VS" info pvd --json | grep -q '"steps": 3' || fail ".pvd did not give 3 steps"
# The same steps as a ParaView file series (JSON), as OpenFOAM's foamToVTK writes them.
echo '{ "file-series-version" : "1.0", "files" : [ { "name" : "s2.vtu", "time" : 2.5 },
  { "name" : "s0.vtu", "time" : 0.5 }, { "name" : "s1.vtu", "time" : 1.5 } ] }' >steps.vtu.series
"$VS" convert steps.vtu.series -o series_json -q
"$VS" info series_json --json | grep -q '"steps": 3' || fail ".series did not give 3 steps"
"$VS" probe series_json --field density --points pts_tets.txt --step 2 >got.txt
"$VS" probe pvd --field density --points pts_tets.txt --step 2 >want_s2.txt
cmp -s got.txt want_s2.txt || fail "the .series' last step differs from the .pvd's"
echo '{ "file-series-version" : "1.0", "files" : [ ] }' >empty.vtu.series
expect_bad_input "a .series without files" convert empty.vtu.series -o bad_series

# VTK's own parallel output (tests/data/vtu/make_vtk_files.py: three pieces with ghost cells) as
# the parts of one .pvd step: the 135 tets of the whole, the same values at its 64 points.
echo '<VTKFile type="Collection"><Collection>' >parts.pvd
for p in 0 1 2; do echo "<DataSet timestep=\"0\" part=\"$p\" file=\"$DATA/vtk_ghosts_$p.vtu\"/>" >>parts.pvd; done
echo '</Collection></VTKFile>' >>parts.pvd
"$VS" convert parts.pvd -o parts -q
"$VS" convert "$DATA/vtk_zlib.vtu" -o whole -q
"$VS" info parts --json | grep -q '"tetra": 135,' || fail "the .pvd's parts did not join into 135 tets"
for x in 0 1 2 3; do for y in 0 1 2 3; do for z in 0 1 2 3; do echo "$x $y $z"; done; done; done >grid_points.txt
"$VS" probe parts --field RTData --points grid_points.txt >got.txt
"$VS" probe whole --field RTData --points grid_points.txt >want.txt
echo -n "parts.pvd: "
compare_probes got.txt want.txt || fail "the .pvd's parts differ from VTK's whole mesh at its points"
grep -q nan got.txt && fail "a grid point of the wavelet probed outside"
# VTK's multiblock of the same tets in two zones and a boundary surface.
"$VS" convert "$DATA/vtk_blocks.vtm" -o blocks -q
"$VS" info blocks --json | grep -q '"tetra": 135,' || fail "the .vtm's zones did not join into 135 tets"
"$VS" probe blocks --field RTData --points grid_points.txt >got.txt
echo -n "vtk_blocks.vtm: "
compare_probes got.txt want.txt || fail "the .vtm's zones differ from VTK's whole mesh at its points"
# --region picks blocks of a .vtm: one zone alone, a name the file lacks, a .vtu refused.
"$VS" convert "$DATA/vtk_blocks.vtm" --region zone_1 -o zone_1 -q
"$VS" info zone_1 --json | grep -q '"tetra": 67,' || fail "the .vtm's block zone_1 is not its 67 tets"
"$VS" info zone_1 | grep -q "VTK XML multiblock vtk_blocks.vtm (blocks zone_1)" || fail "info does not name the block read"
expect_bad_input "a block the .vtm lacks" convert "$DATA/vtk_blocks.vtm" --region zone_7 -o zone_7
expect_bad_input "--region on a .vtu" convert "$DATA/vtk_zlib.vtu" --region zone_1 -o zone_vtu
# The same wavelet as VTK's voxels (read as hexahedra; a wrong corner order would be refused as
# tangled): the same values at the points. (All hexes: the compact encoding's bytes, 344 for 27
# hexes, were refused at load by a bound made for tets before 2026-11-29.)
"$VS" convert "$DATA/vtk_voxels.vtu" -o voxels -q
"$VS" probe voxels --field RTData --points grid_points.txt >got.txt
echo -n "vtk_voxels.vtu: "
compare_probes got.txt want.txt || fail "the voxels differ from VTK's tets at the points"
# VTK's polyhedra (make_vtk_files.py: a cube split where it meets eight hexes, a pyramid and a
# hexagonal prism as polyhedra), from .vtu and legacy 5.1 and 4.2: the linear field f = 1 + 2x +
# 3y + 4z at points of the cube and the hexes (and none outside); the three files probe alike.
LEGACY="$DATA/../vtk"
for x in 0.13 0.9 1.7 2.2 2.95 3.8; do for y in 0.05 1.1 1.93; do for z in 0.3 1.5; do
  echo "$x $y $z"; done; done; done >poly_points.txt
awk '{ printf "%.9g\n", 1 + 2 * $1 + 3 * $2 + 4 * $3 }' poly_points.txt >poly_want.txt
for f in "$DATA/vtk_polyhedra.vtu" "$LEGACY/vtk_polyhedra.vtk" "$LEGACY/vtk_polyhedra_42.vtk"; do
  name=$(basename "$f" | tr . _)
  "$VS" convert "$f" -o "$name" -q
  "$VS" info "$name" --json | grep -q '"pyramid": 12,' || fail "$f: not 12 pyramids after the split"
  "$VS" probe "$name" --field f --points poly_points.txt >"$name.txt"
  echo -n "$(basename "$f"): "
  compare_probes "$name.txt" poly_want.txt || fail "$f: the polyhedra do not reproduce the linear field"
done
echo -n "legacy 4.2 against .vtu: "
compare_probes vtk_polyhedra_42_vtk.txt vtk_polyhedra_vtu.txt || fail "the legacy polyhedra probe otherwise"
# EnSight Gold (tests/data/ensight/make_ensight_files.py): the ASCII and the big-endian binary
# case give two steps at times 0 and 0.5, the linear field (+ 10 at the second step) at the same
# points, and probe alike.
for form in ascii big_endian; do
  "$VS" convert "$DATA/../ensight/$form/mesh.case" -o "ens_$form" -q
  "$VS" info "ens_$form" | grep -q "steps     2 (t = 0 .. 0.5)" || fail "$form EnSight case: not 2 steps at 0 and 0.5"
  head -12 poly_points.txt >ens_points.txt
  "$VS" probe "ens_$form" --field f --step 1 --points ens_points.txt >"ens_$form.txt"
done
awk '{ printf "%.9g\n", 11 + 2 * $1 + 3 * $2 + 4 * $3 }' ens_points.txt >ens_want.txt
echo -n "EnSight ASCII: "
compare_probes ens_ascii.txt ens_want.txt || fail "the EnSight case does not reproduce the linear field"
echo -n "EnSight big-endian binary against ASCII: "
compare_probes ens_big_endian.txt ens_ascii.txt || fail "the binary EnSight case probes otherwise"
"$VS" convert "$DATA/../ensight/ascii/mesh.case" --region 2 -o ens_part2 -q  # one part alone, by number
"$VS" info ens_part2 | grep -q "mesh      18 vertices, 4 elements" || fail "EnSight --region 2: not part 2's hexes alone"
expect_bad_input "an EnSight part the geometry lacks" convert "$DATA/../ensight/ascii/mesh.case" --region fluid -o ens_fluid

# VTK's quadratic cells (make_vtk_files.py: one of each type, curved), from .vtu and legacy .vtk,
# and the EnSight ones as VTK's writer writes them: g = xy + z^2 + x^2 where VTK's shape functions
# put each node and face and body centre (vtk_quadratic_probes.txt; the pyramid's apex, where a
# pyramid's map is singular, left out), and the .vtu's split into 32 hexahedra.
grep -v '^#' "$DATA/vtk_quadratic_probes.txt" | awk 'NR != 132' >quad_rows.txt
cut -d' ' -f1-3 quad_rows.txt >quad_points.txt
cut -d' ' -f4 quad_rows.txt >quad_want.txt
for f in "$DATA/vtk_quadratic.vtu" "$LEGACY/vtk_quadratic.vtk"; do
  name=$(basename "$f" | tr . _)
  "$VS" convert "$f" -o "$name" -q
  "$VS" info "$name" --json | grep -q '"hexahedron": 32,' || fail "$f: not 32 hexahedra after the split"
  "$VS" probe "$name" --field g --points quad_points.txt >"$name.txt"
  echo -n "$(basename "$f"): "
  compare_probes "$name.txt" quad_want.txt || fail "$f: the quadratic cells' nodes and centres are not VTK's"
done
"$VS" convert "$DATA/../ensight/vtk_quadratic/quadratic.0.case" -o ens_quadratic -q
"$VS" info ens_quadratic --json | grep -q '"hexahedron": 16,' || fail "EnSight hexa20: not 16 hexahedra"
awk '$1 < 2.5 || ($1 > 4.5 && $1 < 8.5) || ($1 > 10.5 && $1 < 12.5)' quad_points.txt >ens_quad_points.txt
"$VS" probe ens_quadratic --field g_n --points ens_quad_points.txt >ens_quad.txt
"$VS" probe vtk_quadratic_vtu --field g --points ens_quad_points.txt >ens_quad_want.txt
echo -n "EnSight tetra10, pyramid13, penta15, hexa20: "
compare_probes ens_quad.txt ens_quad_want.txt || fail "the EnSight quadratic elements probe otherwise than the .vtu's"

# Exodus II (tests/data/exodus/make_exodus_files.py): three steps at their times; step 1's field
# and vector probe as the .vtu VTK wrote of it; the quadratic elements as the .vtu's quadratic
# cells; a file cut short is one line and exit 2. (Skipped in a build without NetCDF.)
EXO="$DATA/../exodus"
# NetCDF and CGNS (and HDF5, curl, gnutls under them) load at the first such file, not at every
# start of volstream (io/shared_library.h): the executable does not link them.
if command -v ldd >/dev/null && ldd "$VS" | grep -E 'lib(netcdf|cgns|hdf5)'; then
  fail "volstream links NetCDF, CGNS or HDF5, which cost every command its start"
fi
if "$VS" convert "$EXO/exodus_mixed.exo" -o exo_mixed -q 2>exo_err.txt; then
  "$VS" info exo_mixed | grep -q "steps     3 (t = 0 .. 1.25)" || fail "Exodus: not 3 steps from 0 to 1.25"
  "$VS" info exo_mixed | grep -q "Exodus II exodus_mixed.exo (64-bit offset: HEX8 x 8, PYRAMID5 x 48, TETRA x 48, WEDGE6 x 16; 3 steps)" ||
    fail "Exodus: info does not name the file, its form and blocks"
  "$VS" convert "$EXO/exodus_mixed_1.vtu" -o exo_vtu -q
  random_points exo_vtu 2000 7 >exo_points.txt
  for field in g vel_x; do  # vel_x: a component of the vector vel (vel_x, vel_y, vel_z in the file)
    "$VS" probe exo_mixed --field $field --step 1 --points exo_points.txt >exo_$field.txt
    "$VS" probe exo_vtu --field $field --points exo_points.txt >exo_${field}_want.txt
    echo -n "Exodus step 1 $field against VTK's .vtu: "
    compare_probes exo_$field.txt exo_${field}_want.txt || fail "the Exodus file's $field probes otherwise than the .vtu"
  done
  "$VS" convert "$EXO/exodus_quadratic.exo" -o exo_quadratic -q
  "$VS" convert "$EXO/exodus_quadratic.vtu" -o exo_quadratic_vtu -q
  "$VS" probe exo_quadratic --field g --points ens_quad_points.txt >exo_quad.txt
  "$VS" probe exo_quadratic_vtu --field g --points ens_quad_points.txt >exo_quad_want.txt
  echo -n "Exodus HEX20, HEX27, TETRA10, WEDGE15, PYRAMID13: "
  compare_probes exo_quad.txt exo_quad_want.txt || fail "the Exodus quadratic elements probe otherwise than the .vtu's"
  "$VS" convert "$EXO/exodus_mixed.exo.2.1" -o exo_ranks -q  # one rank file names its set
  "$VS" probe exo_ranks --field g --step 1 --points exo_points.txt >exo_ranks_g.txt
  echo -n "Exodus rank files joined against the whole file: "
  compare_probes exo_ranks_g.txt exo_g.txt || fail "the joined rank files probe otherwise than the whole file"
  cp "$EXO/exodus_mixed.exo.2.0" lonely.e.2.0
  expect_bad_input "a rank file of a set missing" convert lonely.e.2.0 -o lonely
  "$VS" convert "$EXO/exodus_mixed.exo" --region 20 -o exo_hexes -q  # one element block, by id
  "$VS" info exo_hexes | grep -q "HEX8 x 8; blocks read: 20" || fail "Exodus --region 20: info"
  "$VS" info exo_hexes | grep -q "mesh      27 vertices, 8 elements" || fail "Exodus --region 20: not the hexes alone"
  expect_bad_input "an Exodus element block the file lacks" convert "$EXO/exodus_mixed.exo" --region 60 -o exo_60
  head -c 9000 "$EXO/exodus_mixed.exo" >cut.exo
  expect_bad_input "truncated: its variables need 27404 bytes, the file has 9000" convert cut.exo -o cut_exo
else
  grep -q "built without the NetCDF library" exo_err.txt || fail "Exodus: $(cat exo_err.txt)"
  echo "Exodus: skipped (built without NetCDF)"
fi

# CGNS (tests/data/cgns/make_cgns_files.py): an unstructured and a structured zone over three
# steps probe as the .vtu VTK wrote of step 1; the quadratic sections as the .vtu's cells; the
# polyhedral zone (NGON_n, NFACE_n) as VTK's polyhedra above; a file cut short is one line and
# exit 2. (Skipped in a build without the CGNS library.)
CG="$DATA/../cgns"
if "$VS" convert "$CG/cgns_mixed.cgns" -o cg_mixed -q 2>cg_err.txt; then
  "$VS" info cg_mixed | grep -q "steps     3 (t = 0 .. 1.25)" || fail "CGNS: not 3 steps from 0 to 1.25"
  "$VS" convert "$CG/cgns_mixed_1.vtu" -o cg_vtu -q
  random_points cg_vtu 2000 11 >cg_points.txt
  "$VS" probe cg_mixed --field g --step 1 --points cg_points.txt >cg_g.txt
  "$VS" probe cg_vtu --field g --points cg_points.txt >cg_g_want.txt
  echo -n "CGNS zones at step 1 against VTK's .vtu: "
  compare_probes cg_g.txt cg_g_want.txt || fail "the CGNS file probes otherwise than the .vtu"
  "$VS" convert "$CG/cgns_quadratic.cgns" -o cg_quadratic -q
  "$VS" convert "$CG/cgns_quadratic.vtu" -o cg_quadratic_vtu -q
  "$VS" probe cg_quadratic --field g --points ens_quad_points.txt >cg_quad.txt
  "$VS" probe cg_quadratic_vtu --field g --points ens_quad_points.txt >cg_quad_want.txt
  echo -n "CGNS TETRA_10, PYRA_13, PENTA_15, HEXA_20, HEXA_27: "
  compare_probes cg_quad.txt cg_quad_want.txt || fail "the CGNS quadratic sections probe otherwise than the .vtu's"
  "$VS" convert "$CG/cgns_polyhedra.cgns" -o cg_polyhedra -q
  "$VS" probe cg_polyhedra --field f --points poly_points.txt >cg_poly.txt
  echo -n "CGNS NGON_n and NFACE_n: "
  compare_probes cg_poly.txt poly_want.txt || fail "the CGNS polyhedra do not reproduce the linear field"
  head -c 40000 "$CG/cgns_mixed.cgns" >cut.cgns
  expect_bad_input "a CGNS file cut short" convert cut.cgns -o cut_cgns
  "$VS" convert "$CG/cgns_mixed.cgns" --region block -o cg_block -q  # one zone alone
  "$VS" info cg_block | grep -q "1 zone read (block, structured): HEXA_8 (structured) x 24" || fail "CGNS --region: info"
  expect_bad_input "a CGNS zone the file lacks" convert "$CG/cgns_mixed.cgns" --region fluid -o cg_fluid
else
  grep -q "built without the CGNS library" cg_err.txt || fail "CGNS: $(cat cg_err.txt)"
  echo "CGNS: skipped (built without CGNS)"
fi

# Gmsh MSH (tests/data/gmsh/make_gmsh_files.py): a tet mesh's three steps at their times, the
# same in MSH 4.1 binary and 2.2 ascii; g where Gmsh's own basis functions put it, through linear
# and (curved) second-order elements; a file cut short and 14-node pyramids are one line and exit 2.
GM="$DATA/../gmsh"
"$VS" convert "$GM/gmsh_tets_41b.msh" -o gm_41b -q
"$VS" info gm_41b | grep -q "steps     3 (t = 0 .. 1.25)" || fail "Gmsh: not 3 steps from 0 to 1.25"
"$VS" info gm_41b | grep -q "Gmsh gmsh_tets_41b.msh (MSH 4.1 binary: tet4 x 261; 3 steps)" ||
  fail "Gmsh: info does not name the file, its version and elements"
"$VS" convert "$GM/gmsh_tets_22a.msh" -o gm_22a -q
random_points gm_41b 2000 13 >gm_points.txt
for field in g vel_y pressure; do
  "$VS" probe gm_41b --field $field --step 2 --points gm_points.txt >gm_41b_$field.txt
  "$VS" probe gm_22a --field $field --step 2 --points gm_points.txt >gm_22a_$field.txt
  echo -n "Gmsh step 2 $field, MSH 4.1 binary against 2.2 ascii: "
  compare_probes gm_41b_$field.txt gm_22a_$field.txt || fail "the Gmsh encodings' $field differ"
done
for stem in tets_41b:tets mixed:mixed serendipity:serendipity; do
  "$VS" convert "$GM/gmsh_${stem%%:*}.msh" -o gm_${stem%%:*} -q
  grep -v '^#' "$GM/gmsh_${stem#*:}_probes.txt" | awk '{print $2, $3, $4}' >gm_probe_points.txt
  grep -v '^#' "$GM/gmsh_${stem#*:}_probes.txt" | awk '{print $5}' >gm_probe_want.txt
  "$VS" probe gm_${stem%%:*} --field g --points gm_probe_points.txt >gm_probe_got.txt
  echo -n "Gmsh ${stem#*:} elements against Gmsh's basis functions: "
  compare_probes gm_probe_got.txt gm_probe_want.txt || fail "the Gmsh ${stem#*:} file's g differs from Gmsh's"
done
head -c 20000 "$GM/gmsh_tets_41b.msh" >cut.msh
expect_bad_input "a Gmsh file cut short" convert cut.msh -o cut_msh
expect_bad_input "14-node pyramids" convert "$GM/gmsh_pyramid14.msh" -o gm_pyr14
# Physical groups (--region) by name and number, overlapping; 2.2's copies of an element in two
# groups read once: the 2.2 file probes as the 4.1 file, group by group.
for file in 41 22; do
  "$VS" convert "$GM/gmsh_groups_$file.msh" --region top --region 8 -o gm_groups_$file -q
  "$VS" info gm_groups_$file | grep -q "physical groups read: 8 (prisms) 9 (top)" || fail "Gmsh --region: info"
  "$VS" info gm_groups_$file | grep -q " 169 elements" || fail "Gmsh --region top --region 8: not 169 elements"
done
random_points gm_groups_41 2000 17 >gm_group_points.txt
"$VS" probe gm_groups_41 --field f --points gm_group_points.txt >gm_groups_41.txt
"$VS" probe gm_groups_22 --field f --points gm_group_points.txt >gm_groups_22.txt
echo -n "Gmsh physical groups, MSH 4.1 against 2.2: "
compare_probes gm_groups_41.txt gm_groups_22.txt || fail "the Gmsh files' groups differ"
expect_bad_input "a Gmsh physical group of surfaces" convert "$GM/gmsh_groups_41.msh" --region bottom -o gm_bottom
# A series of .msh files: the same groups at every step (here the same mesh twice, 4.1 and 2.2).
"$VS" convert "$GM/gmsh_groups_41b.msh" "$GM/gmsh_groups_22.msh" --region prisms -o gm_series_prisms -q
"$VS" info gm_series_prisms | grep -q "Gmsh gmsh_groups_41b.msh (2 steps; physical groups prisms)" ||
  fail "Gmsh series --region: info"
"$VS" info gm_series_prisms | grep -q " 28 elements" || fail "Gmsh series --region prisms: not 28 elements"
# Fluent (tests/data/fluent/make_fluent_files.py): a binary case and two data files are two steps
# at their flow times; step 1's cell values probe as the .vtu VTK wrote; the ASCII case alone
# finds its .dat by name; a data file cut short and a 2D case are one line and exit 2.
FL="$DATA/../fluent"
"$VS" convert "$FL/fluent_mixed_bin.cas" "$FL/fluent_mixed_bin.dat" "$FL/fluent_mixed_bin-2.dat" -o fl_mixed -q
"$VS" info fl_mixed | grep -q "Fluent case fluent_mixed_bin.cas (2 cell zones (fluid, solid): hex x 8, pyramid x 48, tet x 48, wedge x 16; 2 steps)" ||
  fail "Fluent: info does not describe the case"
"$VS" info fl_mixed | grep -q "steps     2 (t = 0.5 .. 1.25)" || fail "Fluent: not 2 steps from 0.5 to 1.25"
"$VS" convert "$FL/fluent_mixed_2.vtu" -o fl_vtu -q
random_points fl_vtu 2000 12 >fl_points.txt
"$VS" probe fl_mixed --field temperature --step 1 --points fl_points.txt >fl_t.txt
"$VS" probe fl_vtu --field temperature --points fl_points.txt >fl_t_want.txt
echo -n "Fluent binary case, step 1, against VTK's .vtu: "
compare_probes fl_t.txt fl_t_want.txt || fail "the Fluent case probes otherwise than the .vtu"
"$VS" convert "$FL/fluent_mixed.cas" -o fl_ascii -q
"$VS" info fl_ascii | grep -q "Fluent case fluent_mixed.cas" || fail "Fluent: the ASCII case alone"
head -c 3000 "$FL/fluent_mixed_bin-2.dat" >cut.dat
expect_bad_input "a Fluent data file cut short" convert "$FL/fluent_mixed_bin.cas" cut.dat -o cut_fluent
sed 's/^(2 3)$/(2 2)/' "$FL/fluent_mixed.cas" >flat.cas
expect_bad_input "a 2D Fluent case" convert flat.cas -o flat_fluent
# A cell zone alone (--region): the fluid's probes are the whole case's where the fluid is (to a
# relative 1e-5: the points' averages are summed in another order), NaN elsewhere; a zone the
# case lacks is one line.
"$VS" convert "$FL/fluent_mixed_bin.cas" "$FL/fluent_mixed_bin.dat" "$FL/fluent_mixed_bin-2.dat" --region fluid \
  -o fl_fluid -q
"$VS" info fl_fluid | grep -q "2 cell zones (fluid, solid; read: fluid)" || fail "Fluent --region: info"
"$VS" probe fl_fluid --field temperature --step 1 --points fl_points.txt >fl_t_fluid.txt
paste fl_t_fluid.txt fl_t.txt | awk '$1 != "nan" { n++; d = $1 - $2; if (d < 0) d = -d; if (d > 1e-5 * $2) bad++ }
  END { exit (bad || n == 0) }' || fail "Fluent --region fluid: not the whole case's values"
[ "$(grep -c nan fl_t_fluid.txt)" -gt "$(grep -c nan fl_t.txt)" ] || fail "Fluent --region fluid: the solid is still there"
expect_bad_input "a Fluent cell zone the case lacks" convert "$FL/fluent_mixed_bin.cas" --region air -o fl_air
# OpenFOAM (tests/data/openfoam/make_openfoam_files.sh, made with OpenFOAM itself): the ascii
# case's directory is 3 steps at its time directories' values; its binary copy, given by its .foam
# file, probes as the ascii one at the last step; a decomposed case and a faces file cut short are
# one line and exit 2.
OF="$DATA/../openfoam"
"$VS" convert "$OF/box_ascii" -o of_ascii -q
"$VS" info of_ascii | grep -q "steps     3 (t = 0 .. 0.2)" || fail "OpenFOAM: not 3 steps from 0 to 0.2"
"$VS" info of_ascii | grep -q "OpenFOAM case box_ascii (232 cells, 842 faces; fields C, T, U, V; left out" ||
  fail "OpenFOAM: info does not describe the case"
"$VS" convert "$OF/box_binary/box_binary.foam" -o of_binary -q
random_points of_ascii 2000 14 >of_points.txt
"$VS" probe of_ascii --field T --step 2 --points of_points.txt >of_t.txt
"$VS" probe of_binary --field T --points of_points.txt >of_t_want.txt
echo -n "OpenFOAM binary case against the ascii one: "
compare_probes of_t.txt of_t_want.txt || fail "the OpenFOAM binary case probes otherwise than the ascii one"
mkdir -p of_decomposed/processor0/constant of_cut
expect_bad_input "a decomposed OpenFOAM case" convert of_decomposed -o of_decomposed_out
cp -r "$OF/box_ascii/constant" "$OF/box_ascii/system" of_cut/
head -c 5000 "$OF/box_ascii/constant/polyMesh/faces" >of_cut/constant/polyMesh/faces
expect_bad_input "an OpenFOAM faces file cut short" convert of_cut -o of_cut_out
# A collated decomposed case (processors3/, every processor's blocks in each file) probes as the
# binary case it was decomposed from.
"$VS" convert "$OF/box_collated_binary" -o of_collated -q
"$VS" probe of_collated --field T --points of_points.txt >of_t_collated.txt
echo -n "OpenFOAM collated case against the case it came from: "
compare_probes of_t_collated.txt of_t_want.txt || fail "the OpenFOAM collated case probes otherwise"
# A multi-region case: its regions joined, or one asked for; the solid has no U (NaN there).
"$VS" convert "$OF/box_regions" -o of_regions -q
"$VS" info of_regions | grep -q "regions (cells) fluid 116, solid 116" || fail "OpenFOAM: info does not name the regions"
printf '0.3 0.5 0.4\n1.0 0.5 0.4\n' >of_region_points.txt
"$VS" probe of_regions --field U --points of_region_points.txt >of_u.txt
[ "$(head -1 of_u.txt)" = nan ] && [ "$(tail -1 of_u.txt)" != nan ] || fail "OpenFOAM regions: U not NaN in the solid alone"
"$VS" convert "$OF/box_regions" --region fluid -o of_fluid -q
"$VS" probe of_fluid --field U --points of_region_points.txt >of_u_fluid.txt
[ "$(head -1 of_u_fluid.txt)" = nan ] && [ "$(tail -1 of_u_fluid.txt)" = "$(tail -1 of_u.txt)" ] ||
  fail "OpenFOAM --region fluid: not the fluid's values alone"
expect_bad_input "an OpenFOAM region the case lacks" convert "$OF/box_regions" --region gas -o of_gas
# The same case as foamToVTK exports it (tests/data/vtu/make_foam_to_vtk.sh: a .vtm whose blocks
# are the regions, each its volume and its patches), its last step: each region by --region is
# the case's region, cell for cell (T of the cells, at points all over both).
random_points of_regions 2000 13 >of_region_random.txt
for region in fluid solid; do
  "$VS" convert "$DATA/foam_regions/case-regions.vtm.series" --region "$region" -o "ftv_$region" -q
  "$VS" convert "$OF/box_regions" --region "$region" -o "of_only_$region" -q
  "$VS" probe "ftv_$region" --field T_cell --points of_region_random.txt >ftv_t.txt
  "$VS" probe "of_only_$region" --field T --step 2 --points of_region_random.txt >of_t.txt
  echo -n "foamToVTK's .vtm, block $region, against the case's region: "
  compare_probes ftv_t.txt of_t.txt || fail "the .vtm's block $region is not the OpenFOAM case's region $region"
done

# Bad input: a truncated file, a .pvd whose steps have different meshes, an unknown scalars spec.
head -c 3000 m.vtu >trunc.vtu
expect_bad_input "truncated .vtu" convert trunc.vtu -o bad1
"$VS" demo tets --elements 500 --steps 1 -o tmp_small -q --write-mesh small.vtu
sed 's/s1.vtu/small.vtu/' series.pvd >mixed_meshes.pvd
expect_bad_input ".pvd with different meshes" convert mixed_meshes.pvd -o bad2
expect_bad_input "--scalars without =" convert m.lb8.ugrid --scalars linear -o bad3
expect_bad_input "block integrator on a mesh" render holes -o x.png --integrator blocks
# The compact encoding (the default) and the reference one give the same probes and pictures;
# info reports the compact bytes; reference-only requests and damaged compact files are one line.
"$VS" demo mixed --elements 4000 --steps 1 -o mixed_ref -q --encoding reference
grep -q '"mesh_encoding": "compact"' mixed/manifest.json || fail "demo did not store the compact encoding"
grep -q '"mesh_encoding": "reference"' mixed_ref/manifest.json || fail "--encoding reference not stored"
"$VS" probe mixed --field density --points pts_mixed.txt >compact.txt
"$VS" probe mixed_ref --field density --points pts_mixed.txt >reference.txt
echo -n "compact vs reference: "
compare_probes compact.txt reference.txt || fail "the compact dataset probes other values"
"$VS" render mixed -o compact.png --size 64x64 >/dev/null
"$VS" render mixed_ref -o reference.png --size 64x64 >/dev/null
cmp -s compact.png reference.png || fail "the compact dataset renders another picture"
"$VS" info mixed --json | grep -q '"leaf_bvh_nodes"' || fail "info shows no compact resident bytes"
expect_bad_input "reference encoding of a compact dataset" render mixed -o x.png --encoding reference
cp -r mixed broken
head -c 1000 mixed/compact_bytes.bin >broken/compact_bytes.bin
expect_bad_input "truncated compact indices" probe broken --points pts_mixed.txt
grep -q compact_bytes.bin "$WORK/err.txt" || fail "the error does not name the damaged file"
# The reference encoding stores the tets' walk records; a dataset without them (written before
# they were stored) builds them and draws the same picture; a damaged record file is one line.
"$VS" demo tets --elements 4000 --steps 1 -o tets_ref -q --encoding reference
[ -s tets_ref/mesh_tet_walk.bin ] || fail "no walk records stored"
for f in mesh_tet_walk mesh_neighbors mesh_bvh_nodes; do  # info's bytes are the files' sizes
  "$VS" info tets_ref --json | grep -q "\"$f\": $(stat -c %s tets_ref/$f.bin)," || fail "info's bytes of $f.bin"
done
# A copy of tets_ref as written before FILE... were stored: without them and their manifest KEY;
# it must draw tets_ref's picture.
draws_the_same_without() {  # DIR KEY FILE...
  local dir="$1" key="$2"
  shift 2
  cp -r tets_ref "$dir"
  for f in "$@"; do rm "$dir/$f"; done
  /usr/bin/python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); del m[sys.argv[2]]; json.dump(m, open(sys.argv[1],"w"))' \
    "$dir/manifest.json" "$key"
  "$VS" render "$dir" -o "$dir.png" --size 64x64 >/dev/null
  cmp -s stored.png "$dir.png" || fail "without $*: another picture"
}
# A copy of tets_ref with FILE cut short by BYTES: one line naming the file.
refused_when_cut() {  # DIR FILE BYTES WHAT
  cp -r tets_ref "$1" && truncate -s "-$3" "$1/$2"
  expect_bad_input "$4" render "$1" -o x.png --size 16x16
  grep -q "$2" "$WORK/err.txt" || fail "the error does not name $2"
}
"$VS" render tets_ref -o stored.png --size 64x64 >/dev/null
draws_the_same_without tets_old tet_walk_records mesh_tet_walk.bin
refused_when_cut walk_short mesh_tet_walk.bin 64 "truncated walk records"
cp -r tets_ref walk_bad && printf '\377\377\377\377' | dd of=walk_bad/mesh_tet_walk.bin bs=1 seek=640 conv=notrunc 2>/dev/null
expect_bad_input "a walk record that is not its element's" render walk_bad -o x.png --size 16x16
"$VS" probe walk_bad --field density --points pts_tets.txt >/dev/null || fail "probes need no walk records"
# The reference encoding stores each macrocell's vertex list, which a render reads its ranges from;
# a dataset without them (written before) passes over the elements and draws the same picture;
# a list that misses a corner, or lists cut short, are one line naming the file.
[ -s tets_ref/mesh_region_vertices.bin ] && [ -s tets_ref/mesh_region_first.bin ] || fail "no region vertex lists stored"
"$VS" info tets_ref --json | grep -q '"macrocell_vertex_lists"' || fail "info shows no region vertex lists"
draws_the_same_without lists_old region_vertices mesh_region_first.bin mesh_region_vertices.bin
refused_when_cut lists_short mesh_region_vertices.bin 4 "truncated region vertex lists"
cp -r tets_ref lists_bad && printf '\377\377\377\177' | dd of=lists_bad/mesh_region_vertices.bin bs=1 seek=0 conv=notrunc 2>/dev/null
expect_bad_input "a region vertex list that is not the mesh's" render lists_bad -o x.png --size 16x16
echo "mesh CLI ok"
