#!/usr/bin/env bash
# Solvers' files (Exodus II, CGNS): how long `volstream convert` takes for a time series in one
# file, beside VTK's own reader (vtkExodusIIReader, vtkCGNSReader: what ParaView opens them with)
# reading the same steps, and beside `volstream convert` of the same mesh as a .vtu (one step), all
# in one run. (Until commit b0308b3 this was bench/exodus_convert.sh, Exodus only.)
#
# For each demo mesh (tets with TETS elements, mixed with MIXED; 0 skips one):
#   1. volstream demo NAME --elements N --steps 1 --write-mesh NAME_N.vtu (once, reused)
#   2. bench/vtu_to_exodus.py: NAME_N.exo (64-bit offset) and NAME_N_nc4.exo (NetCDF-4, zlib);
#      bench/vtu_to_cgns.py: NAME_N.cgns (HDF5); STEPS steps of the .vtu's point arrays
#   3. REPEATS rounds, in turn: volstream convert of the .vtu, of the .exo, of the _nc4.exo, of
#      the .cgns (whole command, the dataset removed first), and VTK's reader reading every step
#      of each (bench/vtk_solver_read.py: one update per step, all arrays on); "of which
#      reading" is the read stage convert prints (all steps' files, the split, the checks)
# Prints median [min..max] of every figure and a markdown table (OUT/table.md); the summary goes to
# LOGS/solver_files_convert_<date>.log.
#
# With POLYHEDRA=FILE.vtu, also that mesh's .vtu against a CGNS file of its cells as NFACE_n
# polyhedra (bench/vtu_to_cgns.py --polyhedra).
#
# usage: bench/solver_files_convert.sh OUT_DIR [TETS=1e6] [MIXED=5e5]
#        VS=build/volstream REPEATS=3 STEPS=8 LOGS=bench/logs POLYHEDRA=
# Installs python3-vtk9 and python3-netcdf4 with apt-get when they are missing.
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/.." && pwd)"
OUT="$1"
TETS="${2:-1e6}"
MIXED="${3:-5e5}"
VS="$(realpath "${VS:-$REPO/build/volstream}")"
REPEATS="${REPEATS:-3}"
STEPS="${STEPS:-8}"
LOGS="${LOGS:-$REPO/bench/logs}"
PY=/usr/bin/python3

missing=()
"$PY" -c 'import vtk' 2>/dev/null || missing+=(python3-vtk9)
"$PY" -c 'import netCDF4' 2>/dev/null || missing+=(python3-netcdf4)
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" = 0 ] || SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

mkdir -p "$OUT" "$LOGS"
OUT="$(realpath "$OUT")"
exec > >(tee -a "$LOGS/solver_files_convert_$(date -u +%Y-%m-%d).log") 2>&1
stats() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{ v[NR] = $1 } END {
  m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
  printf "%.3f [%.3f..%.3f]", m, v[1], v[NR] }'; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4f", b - a }'; }

echo "# $(date -u +%FT%TZ) solver_files_convert: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'),"\
  "load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# commit $(git -C "$REPO" rev-parse --short HEAD), binary $VS (sha256 $(sha256sum "$VS" | cut -c1-12)),"\
  "VTK $("$PY" -c 'import vtk; print(vtk.vtkVersion.GetVTKVersion())'), steps $STEPS, repeats $REPEATS"
TABLE="$OUT/table.md"
echo "| mesh | elements | file | MiB | volstream convert s | of which reading s | VTK reads all steps s | VTK read / volstream convert |" >"$TABLE"
echo "|---|---|---|---|---|---|---|---|" >>"$TABLE"

# Times `volstream convert` of each file and VTK's reader on each but the .vtu; one table row each.
time_files() {  # NAME FILE...
  local name="$1"
  shift
  local elements
  elements=$("$VS" convert "$1" -o "$OUT/$name.vs" 2>&1 | grep -o '[0-9]* elements' | head -1)
  declare -A vs_t vtk_t read_t
  for ((i = 1; i <= REPEATS; ++i)); do
    for f in "$@"; do
      rm -rf "$OUT/$name.vs"
      local t0 t1
      t0=$(now); "$VS" convert "$f" -o "$OUT/$name.vs" -q >"$OUT/$name.convert.log"; t1=$(now)
      vs_t[$f]+=" $(elapsed "$t0" "$t1")"
      read_t[$f]+=" $(grep -o '(read [0-9.]*s' "$OUT/$name.convert.log" | grep -o '[0-9.]*')"
      [ "${f%.vtu}" != "$f" ] && continue
      vtk_t[$f]+=" $("$PY" "$HERE/vtk_solver_read.py" "$f")"
    done
  done
  for f in "$@"; do
    local v k ratio="-" steps="$STEPS"
    [ "${f%.vtu}" != "$f" ] && steps=1
    v=$(echo "${vs_t[$f]}" | stats)
    k="-"
    if [ -n "${vtk_t[$f]:-}" ]; then
      k=$(echo "${vtk_t[$f]}" | stats)
      ratio=$(awk -v a="${k%% *}" -v b="${v%% *}" 'BEGIN { printf "%.2fx", a / b }')
    fi
    echo "| $name | $elements | $(basename "$f") ($steps steps) | $(du -m "$f" | cut -f1) | $v | $(echo "${read_t[$f]}" | stats) | $k | $ratio |" | tee -a "$TABLE"
  done
}

run_mesh() {
  local name="$1" n="$2" base="$OUT/$1_$2"
  [ -f "$base.vtu" ] || { "$VS" demo "$name" --elements "$n" --steps 1 -o "$base.demo" --write-mesh "$base.vtu" -q; rm -rf "$base.demo"; }
  [ -f "$base.exo" ] || "$PY" "$HERE/vtu_to_exodus.py" "$base.vtu" "$base.exo" "$STEPS" NETCDF3_64BIT_OFFSET
  [ -f "${base}_nc4.exo" ] || "$PY" "$HERE/vtu_to_exodus.py" "$base.vtu" "${base}_nc4.exo" "$STEPS" NETCDF4
  [ -f "$base.cgns" ] || "$PY" "$HERE/vtu_to_cgns.py" "$base.vtu" "$base.cgns" "$STEPS"
  time_files "$1_$2" "$base.vtu" "$base.exo" "${base}_nc4.exo" "$base.cgns"
}

# A polyhedral mesh (POLYHEDRA=FILE.vtu, e.g. bench/make_refined_polyhedra.py's): its .vtu, and
# the same cells as a CGNS file of NFACE_n polyhedra and NGON_n faces over STEPS steps.
run_polyhedra() {
  local name
  name=$(basename "$1" .vtu)
  [ -f "$OUT/$name.cgns" ] || "$PY" "$HERE/vtu_to_cgns.py" "$1" "$OUT/$name.cgns" "$STEPS" --polyhedra
  time_files "$name" "$1" "$OUT/$name.cgns"
}
[ "$TETS" = 0 ] || run_mesh tets "$TETS"
[ "$MIXED" = 0 ] || run_mesh mixed "$MIXED"
[ -z "${POLYHEDRA:-}" ] || run_polyhedra "$(realpath "$POLYHEDRA")"
cat "$TABLE"
