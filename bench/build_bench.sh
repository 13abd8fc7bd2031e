#!/usr/bin/env bash
# Foundation benchmark: time and peak memory to build the jet demo's dataset (cells, bricks,
# ABRs, values) and, separately, to convert the same cells from ExaBrick files (a real import).
# usage: bench/build_bench.sh VOLSTREAM_BINARY OUT_DIR [CELLS...]
set -euo pipefail
VS="$(realpath "$1")"
OUT="$2"
shift 2
SIZES=("${@:-1e6 1e7}")
mkdir -p "$OUT"
printf "%-8s %-10s %10s %9s %9s %9s %9s %10s %10s %12s\n" cells actual bricks "bricks_s" "abrs_s" "values_s" "total_s" "s/Mcell" "peak_MiB" "topo_B/cell"
for n in ${SIZES[@]}; do
  dir="$OUT/jet_$n"
  rm -rf "$dir"
  /usr/bin/time -v "$VS" demo jet --cells "$n" --steps 1 -o "$dir" -q >"$OUT/demo_$n.log" 2>"$OUT/time_$n.log"
  read -r bricks_s abrs_s values_s < <(sed -E 's/.*bricks ([0-9.]+)s, ABRs ([0-9.]+)s, values ([0-9.]+)s.*/\1 \2 \3/' "$OUT/demo_$n.log")
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s }' "$OUT/time_$n.log")
  peak_kb=$(awk -F': ' '/Maximum resident/ { print $2 }' "$OUT/time_$n.log")
  "$VS" info "$dir" --json >"$OUT/info_$n.json"
  python3 - "$OUT/info_$n.json" "$n" "$bricks_s" "$abrs_s" "$values_s" "$wall" "$peak_kb" <<'PY'
import json, sys
info = json.load(open(sys.argv[1]))
n, b, a, v, wall, peak = sys.argv[2], *map(float, sys.argv[3:8])
cells = info["cells"]; by = info["bytes"]
topo = by["cells"] + by["bricks"] + by["abrs"] + by["abr_brick_lists"]
print("%-8s %-10d %10d %9.2f %9.2f %9.2f %9.2f %10.2f %10.0f %12.1f" % (n, cells, info["bricks"], b, a, v, wall, wall / cells * 1e6, peak / 1024, topo / cells))
PY
done
