#!/usr/bin/env bash
# Writes foam_regions/: OpenFOAM's own VTK export of the multi-region test case
# (../openfoam/box_regions), as `foamToVTK -allRegions` leaves it for ParaView: one .vtm a time
# step whose blocks are the regions (fluid, solid), each holding its volume ("internal", a .vtu)
# and a block of its boundary patches (.vtp surfaces); a .vtm.series of the steps. Only the last
# step (0.2) is kept. The tests read a region of it by --region and compare it with the same
# region read from the case itself.
# Usage: bash make_foam_to_vtk.sh   (in this directory; needs Debian's openfoam, OpenFOAM v1912)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/bashrc ]; then
  export WM_PROJECT_DIR=/usr/share/openfoam
fi
command -v foamToVTK >/dev/null || { echo "needs OpenFOAM (foamToVTK): apt-get install openfoam" >&2; exit 1; }
cp -r "$here"/../openfoam/box_regions "$work"/case
# foamToVTK reads each region's schemes, which the test case leaves out: the smallest that do.
for region in fluid solid; do
  mkdir -p "$work"/case/system/$region
  cat >"$work"/case/system/$region/fvSchemes <<'D'
FoamFile { version 2.0; format ascii; class dictionary; object fvSchemes; }
ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; }
divSchemes { default none; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
D
  echo 'FoamFile { version 2.0; format ascii; class dictionary; object fvSolution; }' >"$work"/case/system/$region/fvSolution
done
foamToVTK -allRegions -time 0.2 -case "$work"/case >"$work"/log 2>&1 || { cat "$work"/log >&2; exit 1; }
rm -rf "$here"/foam_regions
cp -r "$work"/case/VTK "$here"/foam_regions
find "$here"/foam_regions -type f | sort | sed "s|$here/||"
du -sh "$here"/foam_regions
