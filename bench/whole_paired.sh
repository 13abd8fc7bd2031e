#!/usr/bin/env bash
# Two volstream binaries' whole `render` command on datasets (meshes or AMR), paired: REPEATS
# rounds, in each every dataset with both binaries one after the other, each command after PAUSE
# seconds of idle.
# PAUSE matters on virtual machines that hand free memory back to the host (free page
# reporting): after a few idle seconds a process's fresh memory faults on the host at first
# touch, which back-to-back runs (PAUSE=0) mostly do not see.
# Prints one line per command (wall, user and system seconds from /usr/bin/time, the render time
# volstream prints), then per dataset the median [min..max] of each for both binaries and of the
# per-round ratio base/new of the wall time.
#
# LOOK: haze or blobs (the mesh looks of bench/umesh_vs_vtk.sh), or default (the dataset's
# default field, transfer function and view: any dataset).
#
# usage: bench/whole_paired.sh BASE NEW DATASET... [REPEATS=5 PAUSE=4 SIZE=512x512 LOOK=haze]
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
BASE="$1" NEW="$2"
shift 2
REPEATS="${REPEATS:-5}" PAUSE="${PAUSE:-4}" SIZE="${SIZE:-512x512}" LOOK="${LOOK:-haze}"
OUT="$(mktemp -d)"
source "$(dirname "$0")/paired_common.sh"
case "$LOOK" in
  haze) mesh_view "$SIZE" 0.02:0.004,0.15:0.004,0.5:0.03,1.1:0.12 ;;
  blobs) mesh_view "$SIZE" 0.02:0,0.15:0,0.5:0.03,1.1:0.12 ;;
  default) VIEW=(--size "$SIZE") ;;
  *) echo "unknown LOOK $LOOK" >&2; exit 2 ;;
esac
VIEW+=(--device cpu)

paired_header "$BASE" "$NEW" "$*" "$REPEATS"
echo "# pause ${PAUSE} s before each command, look $LOOK, size $SIZE"
echo "round binary dataset wall_s user_s sys_s render_s"
for round in $(seq "$REPEATS"); do
  for dataset in "$@"; do
    for which in base new; do
      vs="$BASE"
      [ "$which" = new ] && vs="$NEW"
      sleep "$PAUSE"
      /usr/bin/time -f '%e %U %S' -o "$OUT/time" "$vs" render "$dataset" -o "$OUT/$which.png" "${VIEW[@]}" >"$OUT/log"
      render="$(sed -nE "s/^render $SIZE: ([0-9.]+)s.*/\1/p" "$OUT/log")"
      echo "$round $which $(basename "$dataset") $(cat "$OUT/time") $render"
    done
  done
done | tee "$OUT/runs.txt"

echo
echo "| dataset | binary | wall s | user s | sys s | render s |"
echo "|---|---|---|---|---|---|"
for dataset in "$@"; do
  name="$(basename "$dataset")"
  for which in base new; do
    col() { awk -v w="$which" -v d="$name" -v c="$1" '$2 == w && $3 == d { print $c }' "$OUT/runs.txt" | stats; }
    echo "| $name | $which | $(col 4) | $(col 5) | $(col 6) | $(col 7) |"
  done
  ratio="$(round_ratios "$OUT/runs.txt" "$name" 4 | stats)"
  echo "| $name | wall base/new per round | ${ratio}x | | | |"
done
rm -rf "$OUT"
