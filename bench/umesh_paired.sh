#!/usr/bin/env bash
# Two volstream binaries rendering one mesh dataset, paired: REPEATS rounds, each round both
# encodings (reference and compact; a reference dataset renders compact too, built at load) and
# in each both binaries one after the other, so they see the same machine load. The view and
# transfer function are the haze look of bench/umesh_compact.py and bench/umesh_vs_vtk.sh.
# Prints one line per render, then per encoding the median [min..max] of the render's wall and
# CPU seconds (as volstream prints them) for each binary and of the per-round ratio base/new.
#
# usage: bench/umesh_paired.sh BASE NEW DATASET [REPEATS=5] [SIZE=512x512]
set -euo pipefail
BASE="$1" NEW="$2" DATASET="$3" REPEATS="${4:-5}" SIZE="${5:-512x512}"
OUT="$(mktemp -d)"
source "$(dirname "$0")/paired_common.sh"
mesh_view "$SIZE" 0.02:0.004,0.15:0.004,0.5:0.03,1.1:0.12
VIEW+=(--device cpu)

paired_header "$BASE" "$NEW" "$DATASET" "$REPEATS"
echo "round binary encoding wall_s cpu_s M_samples"
for round in $(seq "$REPEATS"); do
  for encoding in reference compact; do
    for which in base new; do
      vs="$BASE"
      [ "$which" = new ] && vs="$NEW"
      line="$("$vs" render "$DATASET" -o "$OUT/$which.png" --encoding "$encoding" "${VIEW[@]}" | grep "^render $SIZE")"
      # "render WxH: 1.23s (2.34s CPU time), 9.1 M samples, ..."
      echo "$round $which $encoding $(sed -E 's/.*: ([0-9.]+)s \(([0-9.]+)s CPU time\), ([0-9.]+) M samples.*/\1 \2 \3/' <<<"$line")"
    done
  done
done | tee "$OUT/runs.txt"

echo
echo "| encoding | base wall s | new wall s | base CPU s | new CPU s | CPU base/new per round |"
echo "|---|---|---|---|---|---|"
for encoding in reference compact; do
  col() { awk -v w="$1" -v e="$encoding" -v c="$2" '$2 == w && $3 == e { print $c }' "$OUT/runs.txt" | stats; }
  ratio="$(round_ratios "$OUT/runs.txt" "$encoding" 5 | stats)"
  echo "| $encoding | $(col base 4) | $(col new 4) | $(col base 5) | $(col new 5) | ${ratio}x |"
done
rm -rf "$OUT"
