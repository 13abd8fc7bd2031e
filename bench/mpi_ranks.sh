#!/usr/bin/env bash
# Data-parallel rendering (issue 17): per rank the cells (a mesh's elements) it owns and holds
# (ghosts), the value bytes it read, its stages (read, ranges, refit, render, composite) and the
# compositing bytes, for 2..8 ranks (meshes: 2..4) on one demo, plus the image difference to one rank.
# Usage: bench/mpi_ranks.sh [VOLSTREAM] [CELLS] [SIZE] [DEMO] [ENCODING]   (oversubscribes when ranks > cores)
#   DEMO: jet (AMR, default) or a mesh demo (tets, mixed, holes; CELLS is then its element count)
#   ENCODING: meshes, compact (default) or reference
set -euo pipefail
VS="${1:-build/volstream}"
CELLS="${2:-2000000}"
SIZE="${3:-512x512}"
DEMO="${4:-jet}"
ENCODING="${5:-compact}"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
TOOL="$(dirname "$0")/../tests/mpi/mpi_tool.py"
if [ "$DEMO" = jet ]; then
  "$VS" demo jet --cells "$CELLS" --steps 1 -o "$WORK/ds" -q
  OPTIONS=(--field pressure --iso -500)
  COUNTS="1 2 3 4 8"
else
  "$VS" demo "$DEMO" --elements "$CELLS" --steps 1 --encoding "$ENCODING" -o "$WORK/ds" -q
  OPTIONS=(--field density --iso 0.3 --shade)
  COUNTS="1 2 3 4"
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "commit: $(git -C "$(dirname "$0")" rev-parse --short HEAD)"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for n in $COUNTS; do
  echo "== mpirun --oversubscribe -np $n $VS render $DEMO ${OPTIONS[*]} --size $SIZE"
  mpirun --oversubscribe -np "$n" "$VS" render "$WORK/ds" "${OPTIONS[@]}" --size "$SIZE" -o "$WORK/$n.pfm"
  [ "$n" = 1 ] || echo "max |difference| to 1 rank: $(python3 "$TOOL" compare "$WORK/1.pfm" "$WORK/$n.pfm" 1)"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
