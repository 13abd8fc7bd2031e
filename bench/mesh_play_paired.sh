#!/usr/bin/env bash
# Two volstream binaries playing one mesh time series, paired: REPEATS rounds, in each both
# binaries one after the other (the same machine load). Prints each play's per-stage table rows
# for `ranges` and `render` and its frames/s, then per binary the median [min..max] over rounds of
# the ranges stage's total and median ms and of the frames/s. The view and transfer function are
# the blobs look of bench/umesh_vs_vtk.sh.
#
# usage: bench/mesh_play_paired.sh BASE NEW DATASET [REPEATS=3] [SIZE=512x512]
set -euo pipefail
BASE="$1" NEW="$2" DATASET="$3" REPEATS="${4:-3}" SIZE="${5:-512x512}"
OUT="$(mktemp -d)"
source "$(dirname "$0")/paired_common.sh"
mesh_view "$SIZE" 0.02:0,0.15:0,0.5:0.03,1.1:0.12

paired_header "$BASE" "$NEW" "$DATASET" "$REPEATS"
echo "round binary ranges_total_ms ranges_median_ms ranges_max_ms render_median_ms frames_per_s"
for round in $(seq "$REPEATS"); do
  for which in base new; do
    vs="$BASE"
    [ "$which" = new ] && vs="$NEW"
    "$vs" play "$DATASET" -q "${VIEW[@]}" >"$OUT/play.txt" 2>&1
    # "ranges  COUNT  TOTAL  MEAN  MEDIAN  MAX"; "played N frames ... in S s: F frames/s"
    ranges="$(awk '$1 == "ranges" { print $3, $5, $6 }' "$OUT/play.txt")"
    render="$(awk '$1 == "render" { print $5 }' "$OUT/play.txt")"
    fps="$(sed -nE 's/^played .*: ([0-9.]+) frames\/s.*/\1/p' "$OUT/play.txt")"
    echo "$round $which $ranges $render $fps"
  done
done | tee "$OUT/runs.txt"

echo
echo "| binary | ranges total ms | ranges median ms | render median ms | frames/s |"
echo "|---|---|---|---|---|"
for which in base new; do
  col() { awk -v w="$which" -v c="$1" '$2 == w { print $c }' "$OUT/runs.txt" | stats; }
  echo "| $which | $(col 3) | $(col 4) | $(col 6) | $(col 7) |"
done
rm -rf "$OUT"
