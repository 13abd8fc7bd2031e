#!/usr/bin/env bash
# Rebuilds tests/data/openfoam from scratch with OpenFOAM itself (Debian 12's `openfoam`
# package, OpenFOAM v1912; its tools are in /usr/bin) and checks it with VTK's own reader
# (make_openfoam_reference.py, /usr/bin/python3 with python3-vtk9):
#   box_ascii   a 6x5x4 blockMesh box, its corner cells refined (topoSet + refineMesh), so the
#               cells beside them are polyhedra (faces split to meet the smaller cells); three
#               time steps 0, 0.1, 0.2 of scalarTransportFoam (T, U; phi a surface field,
#               skipped), cell centres C and volumes V (postProcess) in every step, mag(U) in
#               the last only (left out); ascii files, faces a faceList
#   box_binary  the same case, foamFormatConvert'ed to binary (faces a faceCompactList)
#   box_gz      the same case, ascii, every file gzipped (writeCompression on)
#   box_decomposed  box_ascii decomposed by decomposePar (method simple) for 3 processors, every
#               time step: the processor directories alone (with each one's pointProcAddressing
#               and the other addressing files decomposePar writes), and controlDict
#   box_collated  box_ascii decomposed as box_decomposed, in OpenFOAM's collated layout
#               (decomposePar -fileHandler collated: processors3/, each file every processor's)
#   box_collated_binary  the same of box_binary (its one time step, binary blocks)
#   box_regions a multi-region case (as chtMultiRegionFoam's): box_ascii's cells cut by
#               topoSet cellZones and splitMeshRegions -cellZonesOnly into regions fluid (x > 0.5)
#               and solid, each time step's fields mapped to both (TIME/fluid, TIME/solid); the
#               solid has no U; constant/polyMesh and the time directories' own fields stay, as
#               the whole mesh (region0); each region's cellRegionAddressing maps its cells to
#               region0's
#   box_regions_decomposed  box_regions decomposed by decomposePar -allRegions for 2 processors,
#               its last time step only (processorN/constant/REGION/polyMesh, processorN/0.2/REGION)
#   reference.vtu  VTK's cells (polyhedra not decomposed) and cell values of the last step, the
#               same for all three copies
# Usage: bash make_openfoam_files.sh   (in this directory; takes a few seconds)
# For bench/: BENCH_N=100 BENCH_CASE=DIR bash make_openfoam_files.sh writes instead the same case
# at N^3 cells with smaller corners refined (1,396,578 cells at N=100), in binary, time steps 0,
# 0.05 and 0.1, to DIR (about 420 MB and two minutes at N=100), and leaves the test data alone.
set -euo pipefail
bench_n=${BENCH_N:-}
if [ -n "$bench_n" ]; then
  [ -n "${BENCH_CASE:-}" ] || { echo "BENCH_N needs BENCH_CASE=DIR" >&2; exit 2; }
  blocks="$bench_n $bench_n $bench_n" low=0.3 high="0.9 0.7 0.5" end_time=0.1 interval=1
else
  blocks="6 5 4" low=0.41 high="0.79 0.59 0.39" end_time=0.2 interval=2
fi
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The tools find their etc/ files (controlDict, cellModels) under WM_PROJECT_DIR.
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/bashrc ]; then
  export WM_PROJECT_DIR=/usr/share/openfoam
fi
for tool in blockMesh topoSet refineMesh setFields scalarTransportFoam postProcess foamFormatConvert decomposePar; do
  command -v $tool >/dev/null || { echo "needs OpenFOAM ($tool): apt-get install openfoam" >&2; exit 1; }
done
version=$(dpkg-query -W -f='${Version}' openfoam 2>/dev/null || echo unknown)

header() {  # header CLASS LOCATION OBJECT
  cat <<H
FoamFile
{
    version     2.0;
    format      ascii;
    class       $1;
    location    "$2";
    object      $3;
}
H
}

c=$work/box
mkdir -p $c/system $c/constant $c/0
{ header dictionary system blockMeshDict; cat <<D
convertToMeters 1;
vertices ((0 0 0) (1.2 0 0) (1.2 1 0) (0 1 0) (0 0 0.8) (1.2 0 0.8) (1.2 1 0.8) (0 1 0.8));
blocks (hex (0 1 2 3 4 5 6 7) ($blocks) simpleGrading (1 1 1));
edges ();
boundary
(
    inlet  { type patch; faces ((0 4 7 3)); }
    outlet { type patch; faces ((1 2 6 5)); }
    walls  { type wall; faces ((0 1 5 4) (3 7 6 2) (0 3 2 1) (4 5 6 7)); }
);
mergePatchPairs ();
D
} > $c/system/blockMeshDict
{ header dictionary system controlDict; cat <<D
application     scalarTransportFoam;
startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         $end_time;
deltaT          0.05;
writeControl    timeStep;
writeInterval   $interval;
purgeWrite      0;
writeFormat     ascii;
writePrecision  10;
writeCompression off;
timeFormat      general;
timePrecision   6;
runTimeModifiable false;
D
} > $c/system/controlDict
{ header dictionary system fvSchemes; cat <<'D'
ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; }
divSchemes { default none; div(phi,T) Gauss linearUpwind grad(T); }
laplacianSchemes { default none; laplacian(DT,T) Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
D
} > $c/system/fvSchemes
{ header dictionary system fvSolution; cat <<'D'
solvers { T { solver PBiCGStab; preconditioner DILU; tolerance 1e-09; relTol 0; } }
SIMPLE { nNonOrthogonalCorrectors 0; }
D
} > $c/system/fvSolution
{ header dictionary system topoSetDict; cat <<D
actions
(
    { name corner; type cellSet; action new; source boxToCell; box (-1 -1 -1) ($low $low $low); }
    { name corner; type cellSet; action add; source boxToCell; box ($high) (2 2 2); }
);
D
} > $c/system/topoSetDict
{ header dictionary system refineMeshDict; cat <<'D'
set corner;
coordinateSystem global;
globalCoeffs { tan1 (1 0 0); tan2 (0 1 0); }
directions (tan1 tan2 normal);
useHexTopology true;
geometricCut false;
writeMesh false;
D
} > $c/system/refineMeshDict
{ header dictionary system setFieldsDict; cat <<'D'
defaultFieldValues ( volScalarFieldValue T 0 volVectorFieldValue U (1 0.2 0.1) );
regions
(
    boxToCell { box (-1 -1 -1) (0.5 0.6 0.5); fieldValues ( volScalarFieldValue T 1 volVectorFieldValue U (0.5 0.4 0.3) ); }
);
D
} > $c/system/setFieldsDict
{ header dictionary constant transportProperties; echo "DT 0.02;"; } > $c/constant/transportProperties
{ header volScalarField 0 T; cat <<'D'
dimensions [0 0 0 0 0 0 0];
internalField uniform 0;
boundaryField
{
    inlet  { type fixedValue; value uniform 1; }
    outlet { type zeroGradient; }
    walls  { type zeroGradient; }
}
D
} > $c/0/T
{ header volVectorField 0 U; cat <<'D'
dimensions [0 1 -1 0 0 0 0];
internalField uniform (1 0.2 0.1);
boundaryField
{
    inlet  { type fixedValue; value uniform (1 0.2 0.1); }
    outlet { type zeroGradient; }
    walls  { type slip; }
}
D
} > $c/0/U

run() { "$@" -case $c > $work/log.$1 2>&1 || { cat $work/log.$1 >&2; exit 1; }; }
run blockMesh
run topoSet
run refineMesh -overwrite
run setFields
run scalarTransportFoam
run postProcess -func writeCellCentres
run postProcess -func writeCellVolumes
[ -n "$bench_n" ] || run postProcess -func 'mag(U)' -time 0.2
rm -rf $c/constant/polyMesh/sets $c/constant/polyMesh/*Level* $c/constant/polyMesh/*Zones* $c/constant/polyMesh/refinementHistory
rm -f $c/*/Cx $c/*/Cy $c/*/Cz
rm -rf $c/*/uniform $c/postProcessing

if [ -n "$bench_n" ]; then
  rm -rf "$BENCH_CASE" && mkdir -p "$BENCH_CASE"
  cp -r $c/0 $c/0.05 $c/0.1 $c/constant $c/system "$BENCH_CASE"/
  touch "$BENCH_CASE"/"$(basename "$BENCH_CASE")".foam
  sed -i 's/^writeFormat .*/writeFormat     binary;/' "$BENCH_CASE"/system/controlDict
  foamFormatConvert -case "$BENCH_CASE" > $work/log.convert 2>&1 || { cat $work/log.convert >&2; exit 1; }
  rm -f "$BENCH_CASE"/*/phi*
  du -sh "$BENCH_CASE"
  exit 0
fi

rm -rf "$here"/box_ascii "$here"/box_binary "$here"/box_gz "$here"/box_decomposed "$here"/box_collated* "$here"/box_regions* \
  "$here"/reference*.vtu
mkdir -p "$here"/box_ascii
cp -r $c/0 $c/0.1 $c/0.2 $c/constant $c/system "$here"/box_ascii/
touch "$here"/box_ascii/box_ascii.foam
cp -r "$here"/box_ascii "$here"/box_binary
mv "$here"/box_binary/box_ascii.foam "$here"/box_binary/box_binary.foam
sed -i 's/^writeFormat .*/writeFormat     binary;/' "$here"/box_binary/system/controlDict
foamFormatConvert -case "$here"/box_binary > $work/log.convert 2>&1 || { cat $work/log.convert >&2; exit 1; }
cp -r "$here"/box_ascii "$here"/box_gz
mv "$here"/box_gz/box_ascii.foam "$here"/box_gz/box_gz.foam
sed -i 's/^writeCompression .*/writeCompression on;/' "$here"/box_gz/system/controlDict
find "$here"/box_gz/constant "$here"/box_gz/0* -type f | xargs gzip -9n
# boundary stays as it is: VTK's reader needs it (volstream does not read it).
for d in "$here"/box_gz; do gunzip "$d"/constant/polyMesh/boundary.gz; done
# Kept small: the binary and gzipped copies hold the mesh and the last step only, and only the
# ascii case's last step keeps phi (a surface field, skipped).
rm -rf "$here"/box_binary/0 "$here"/box_binary/0.1 "$here"/box_gz/0 "$here"/box_gz/0.1
rm -f "$here"/box_ascii/0.1/phi* "$here"/box_binary/0.2/phi* "$here"/box_gz/0.2/phi*
rm -rf "$here"/box_*/system/{fvSchemes,fvSolution,topoSetDict,refineMeshDict,setFieldsDict,blockMeshDict}
d=$work/decomposed
cp -r "$here"/box_ascii $d
{ header dictionary system decomposeParDict; cat <<'D'
numberOfSubdomains 3;
method          simple;
coeffs          { n (3 1 1); }
D
} > $d/system/decomposeParDict
# Every time step (without -time, v1912 decomposes the first alone).
decomposePar -time '0:' -case $d > $work/log.decompose 2>&1 || { cat $work/log.decompose >&2; exit 1; }
mkdir -p "$here"/box_decomposed/system
cp -r $d/processor* "$here"/box_decomposed/
cp $d/system/controlDict "$here"/box_decomposed/system/
touch "$here"/box_decomposed/box_decomposed.foam
for from in ascii binary; do
  d=$work/collated_$from
  to="$here"/box_collated$([ $from = ascii ] || echo _binary)
  cp -r "$here"/box_$from $d
  cp $work/decomposed/system/decomposeParDict $c/system/fvSchemes $c/system/fvSolution $d/system/
  decomposePar -fileHandler collated -time '0:' -case $d > $work/log.collated 2>&1 ||
    { cat $work/log.collated >&2; exit 1; }
  mkdir -p "$to"/system
  cp -r $d/processors3 "$to"/
  cp $d/system/controlDict "$to"/system/
  touch "$to"/$(basename "$to").foam
done

r=$work/regions
cp -r $c $r
rm -rf $r/0.05 $r/0.15 $r/constant/polyMesh/cellZones
{ header dictionary system topoSetDict; cat <<'D'
actions
(
    { name solidCells; type cellSet; action new; source boxToCell; box (-1 -1 -1) (0.5 2 2); }
    { name solid; type cellZoneSet; action new; source setToCellZone; set solidCells; }
    { name fluidCells; type cellSet; action new; source cellToCell; set solidCells; }
    { name fluidCells; type cellSet; action invert; }
    { name fluid; type cellZoneSet; action new; source setToCellZone; set fluidCells; }
);
D
} > $r/system/topoSetDict
{ header dictionary constant regionProperties; echo "regions ( fluid (fluid) solid (solid) );"; } > $r/constant/regionProperties
topoSet -case $r > $work/log.regions 2>&1 || { cat $work/log.regions >&2; exit 1; }
# splitMeshRegions maps the start time's fields: once for each time step.
for t in 0 0.1 0.2; do
  sed -i "s/^startTime .*/startTime       $t;/" $r/system/controlDict
  splitMeshRegions -cellZonesOnly -overwrite -case $r >> $work/log.regions 2>&1 || { cat $work/log.regions >&2; exit 1; }
done
sed -i "s/^startTime .*/startTime       0;/" $r/system/controlDict
rm -rf $r/constant/polyMesh/sets $r/constant/cellToRegion $r/*/cellToRegion $r/*/*/cellToRegion $r/0*/solid/U* $r/0*/*/phi*
rm -rf $r/0*/*/mag* $r/constant/*/polyMesh/*Zones $r/constant/polyMesh/*Zones $r/0/polyMesh
rm -f $r/constant/*/polyMesh/{face,point,boundary}RegionAddressing
mkdir -p "$here"/box_regions
cp -r $r/0 $r/0.1 $r/0.2 $r/constant $r/system "$here"/box_regions/
touch "$here"/box_regions/box_regions.foam
{ header dictionary system decomposeParDict; cat <<'D'
numberOfSubdomains 2;
method          simple;
coeffs          { n (1 2 1); }
D
} > $r/system/decomposeParDict
for region in fluid solid; do mkdir -p $r/system/$region && cp $r/system/decomposeParDict $r/system/$region/; done
decomposePar -allRegions -time 0.2 -case $r > $work/log.decompose_regions 2>&1 || { cat $work/log.decompose_regions >&2; exit 1; }
mkdir -p "$here"/box_regions_decomposed/system
cp -r $r/processor* "$here"/box_regions_decomposed/
cp $r/system/controlDict "$here"/box_regions_decomposed/system/
touch "$here"/box_regions_decomposed/box_regions_decomposed.foam
rm -rf "$here"/box_regions/system/{fvSchemes,fvSolution,topoSetDict,refineMeshDict,setFieldsDict,blockMeshDict,decomposeParDict,fluid,solid}
echo "$version" > "$here"/OPENFOAM_VERSION
/usr/bin/python3 "$here"/make_openfoam_reference.py "$here"
du -sh "$here"
