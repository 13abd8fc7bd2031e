#!/bin/bash
# Paired: new (hole state) vs base (8ac308a), paired-timer -n 10, 512x512.
L=/work/main/bench/logs/hole_state_2026-11-29
H="$(cat /tmp/haze_args)"; Bl="$(cat /tmp/blobs_args)"
for row in "mixed_haze vtk2/mixed_5e5.vs H" "mixed_blobs vtk2/mixed_5e5.vs B" "split_haze vtk1s/mixed_5e5_split.vs H" "split_blobs vtk1s/mixed_5e5_split.vs B" "tets_haze vtk2/tets_1e6.vs H" "tets_blobs vtk2/tets_1e6.vs B" "compact_mixed_haze mixed_c.vs H"; do
  set -- $row
  if [ "$3" = H ]; then A="$H"; else A="$Bl"; fi
  echo "== $1 ($2)"
  paired-timer -n 10 --warmup 2 --timeout 300 --vs "/tmp/v_base0 render /tmp/$2 $A -o /tmp/fb/b.png" -- /tmp/v_new render /tmp/$2 $A -o /tmp/fb/a.png > $L/$1.txt 2>&1
  tail -3 $L/$1.txt
done
