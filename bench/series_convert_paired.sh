#!/usr/bin/env bash
# Whole `volstream convert` of time series, two binaries side by side in one run (hyperfine,
# REPEATS runs each after a warm-up, the dataset removed before each): a foamToVTK-like .vtu
# series of polyhedra (bench/make_refined_polyhedra.py N --all-polyhedra, then
# bench/vtu_series.py, STEPS steps), a Fluent case of N^3 hexes with STEPS data files
# (bench/fluent_box.py) and, where OpenFOAM's tools are installed (apt-get install openfoam), an
# OpenFOAM case of FOAM_N^3 cells with refined corners and 3 time steps
# (tests/data/openfoam/make_openfoam_files.sh with BENCH_N). The inputs are made once in OUT
# and reused.
#
# usage: bench/series_convert_paired.sh BASE_BIN NEW_BIN OUT [POLY_N=64] [FLUENT_N=100]
#        REPEATS=3 STEPS=8 FOAM_N=100
# Writes OUT/{vtu_series,fluent,openfoam}.{txt,json} and prints hyperfine's summaries.
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
HERE="$(cd "$(dirname "$0")" && pwd)"
BASE="$(realpath "$1")" NEW="$(realpath "$2")" OUT="$3"
POLY_N="${4:-64}" FLUENT_N="${5:-100}" REPEATS="${REPEATS:-3}" STEPS="${STEPS:-8}"
PY=/usr/bin/python3
mkdir -p "$OUT"
command -v hyperfine >/dev/null || { echo "needs hyperfine (apt-get install hyperfine)" >&2; exit 2; }

series="$OUT/poly_series/series.vtu.series"
if [ ! -f "$series" ]; then
  "$PY" "$HERE/make_refined_polyhedra.py" "$POLY_N" "$OUT/poly.vtu" --all-polyhedra
  "$PY" "$HERE/vtu_series.py" "$OUT/poly.vtu" "$OUT/poly_series" "$STEPS"
fi
if [ ! -f "$OUT/box.cas" ]; then "$PY" "$HERE/fluent_box.py" "$FLUENT_N" "$OUT/box" "$STEPS"; fi
dats=$(ls "$OUT"/box-*.dat | sort -V | tr '\n' ' ')

paired() {  # NAME ARGS...: both binaries converting ARGS
  local name=$1
  shift
  hyperfine -r "$REPEATS" -w 1 --prepare "rm -rf $OUT/dataset" --export-json "$OUT/$name.json" \
    -n base "$BASE convert $* -o $OUT/dataset -q --encoding reference" \
    -n new "$NEW convert $* -o $OUT/dataset -q --encoding reference" | tee "$OUT/$name.txt"
}
paired vtu_series "$series"
paired fluent "$OUT/box.cas" $dats
if command -v blockMesh >/dev/null; then
  foam="$OUT/foam_box"
  [ -d "$foam" ] || BENCH_N="${FOAM_N:-100}" BENCH_CASE="$foam" bash "$HERE/../tests/data/openfoam/make_openfoam_files.sh"
  paired openfoam "$foam"
else
  echo "no OpenFOAM tools (apt-get install openfoam): the OpenFOAM case is left out" >&2
fi
