#!/usr/bin/env bash
# Whole `volstream convert` of time series and solver cases, two binaries side by side in one run
# (hyperfine, REPEATS runs each after a warm-up, the dataset removed before each), then each
# one's peak memory (/usr/bin/time's maximum resident set, PEAK_ROUNDS rounds, base and new in
# turn): a foamToVTK-like .vtu series of polyhedra (bench/make_refined_polyhedra.py N
# --all-polyhedra, then bench/vtu_series.py, STEPS steps), a Fluent case of N^3 hexes with STEPS
# data files (bench/fluent_box.py), where OpenFOAM's tools are installed (apt-get install
# openfoam) an OpenFOAM case of FOAM_N^3 cells with refined corners and 3 time steps
# (tests/data/openfoam/make_openfoam_files.sh with BENCH_N), and an EnSight Gold case of the 1e6-tet
# demo mesh in two parts (bench/vtu_to_ensight_parts.py: 850,056 and 148,194 tets), whole and
# with `--region 2` (the small part alone). The inputs are made once in OUT and reused.
#
# usage: bench/series_convert_paired.sh BASE_BIN NEW_BIN OUT [POLY_N=64] [FLUENT_N=100]
#        REPEATS=3 STEPS=8 FOAM_N=100 PEAK_ROUNDS=3 ROWS="vtu_series fluent openfoam ensight"
# Writes OUT/NAME.{txt,json} (hyperfine) and OUT/NAME_peak.txt (each round's peak KiB and the
# medians) for each row, and prints both.
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
HERE="$(cd "$(dirname "$0")" && pwd)"
BASE="$(realpath "$1")" NEW="$(realpath "$2")" OUT="$3"
POLY_N="${4:-64}" FLUENT_N="${5:-100}" REPEATS="${REPEATS:-3}" STEPS="${STEPS:-8}"
PEAK_ROUNDS="${PEAK_ROUNDS:-3}" ROWS="${ROWS:-vtu_series fluent openfoam ensight}"
PY=/usr/bin/python3
mkdir -p "$OUT"
command -v hyperfine >/dev/null || { echo "needs hyperfine (apt-get install hyperfine)" >&2; exit 2; }

# NAME ARGS...: both binaries converting ARGS, timed, then their peak memory.
paired() {
  local name=$1
  shift
  hyperfine -r "$REPEATS" -w 1 --prepare "rm -rf $OUT/dataset" --export-json "$OUT/$name.json" \
    -n base "$BASE convert $* -o $OUT/dataset -q --encoding reference" \
    -n new "$NEW convert $* -o $OUT/dataset -q --encoding reference" | tee "$OUT/$name.txt"
  local base_kib=() new_kib=()
  for ((round = 0; round < PEAK_ROUNDS; ++round)); do
    for bin in base new; do
      rm -rf "$OUT/dataset"
      local exe=$BASE
      [ "$bin" = new ] && exe=$NEW
      local kib
      kib=$(/usr/bin/time -f %M "$exe" convert "$@" -o "$OUT/dataset" -q --encoding reference 2>&1 >/dev/null | tail -n 1)
      if [ "$bin" = base ]; then base_kib+=("$kib"); else new_kib+=("$kib"); fi
    done
  done
  median() { printf '%s\n' "$@" | sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
  {
    echo "peak KiB per round (base new): $(paste -d' ' <(printf '%s\n' "${base_kib[@]}") <(printf '%s\n' "${new_kib[@]}") | tr '\n' ',')"
    echo "median peak MiB: base $(($(median "${base_kib[@]}") / 1024)), new $(($(median "${new_kib[@]}") / 1024))"
  } | tee "$OUT/${name}_peak.txt"
}
wants() { [[ " $ROWS " == *" $1 "* ]]; }

if wants vtu_series; then
  series="$OUT/poly_series/series.vtu.series"
  if [ ! -f "$series" ]; then
    "$PY" "$HERE/make_refined_polyhedra.py" "$POLY_N" "$OUT/poly.vtu" --all-polyhedra
    "$PY" "$HERE/vtu_series.py" "$OUT/poly.vtu" "$OUT/poly_series" "$STEPS"
  fi
  paired vtu_series "$series"
fi
if wants fluent; then
  if [ ! -f "$OUT/box.cas" ]; then "$PY" "$HERE/fluent_box.py" "$FLUENT_N" "$OUT/box" "$STEPS"; fi
  dats=$(ls "$OUT"/box-*.dat | sort -V | tr '\n' ' ')
  paired fluent "$OUT/box.cas" $dats
fi
if wants openfoam; then
  if command -v blockMesh >/dev/null; then
    foam="$OUT/foam_box"
    [ -d "$foam" ] || BENCH_N="${FOAM_N:-100}" BENCH_CASE="$foam" bash "$HERE/../tests/data/openfoam/make_openfoam_files.sh"
    paired openfoam "$foam"
  else
    echo "no OpenFOAM tools (apt-get install openfoam): the OpenFOAM case is left out" >&2
  fi
fi
if wants ensight; then
  ensight="$OUT/ensight_parts/parts.0.case"
  if [ ! -f "$ensight" ]; then
    "$NEW" demo tets --elements 1e6 --steps 1 --encoding reference -q -o "$OUT/tets.vs" --write-mesh "$OUT/tets_1e6.vtu"
    "$PY" "$HERE/vtu_to_ensight_parts.py" "$OUT/tets_1e6.vtu" "$OUT/ensight_parts"
  fi
  paired ensight_whole "$ensight"
  paired ensight_region "$ensight" --region 2
fi
