#!/usr/bin/env bash
# Data-parallel rendering (issue 17): per rank the cells it owns and holds (ghosts), the value
# bytes it read, its stages (read, ranges, refit, render, composite) and the compositing bytes,
# for 2..8 ranks on one demo, plus the image difference to one rank.
# Usage: bench/mpi_ranks.sh [VOLSTREAM] [CELLS] [SIZE]   (oversubscribes when ranks > cores)
set -euo pipefail
VS="${1:-build/volstream}"
CELLS="${2:-2000000}"
SIZE="${3:-512x512}"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
TOOL="$(dirname "$0")/../tests/mpi/mpi_tool.py"
"$VS" demo jet --cells "$CELLS" --steps 1 -o "$WORK/jet" -q
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "commit: $(git -C "$(dirname "$0")" rev-parse --short HEAD)"
for n in 1 2 3 4 8; do
  echo "== mpirun --oversubscribe -np $n $VS render jet --iso -500 --field pressure --size $SIZE"
  mpirun --oversubscribe -np "$n" "$VS" render "$WORK/jet" --field pressure --iso -500 --size "$SIZE" \
    -o "$WORK/$n.pfm"
  [ "$n" = 1 ] || echo "max |difference| to 1 rank: $(python3 "$TOOL" compare "$WORK/1.pfm" "$WORK/$n.pfm" 1)"
done
