#!/usr/bin/env bash
# Data-parallel rendering (issue 17): per rank the cells (a mesh's elements) it owns and holds
# (ghosts), the value bytes it read, its stages (read, ranges, refit, render, composite) and the
# compositing bytes, for 2..8 ranks (meshes: 2..4) on one demo, plus the image difference to one rank.
# Usage: bench/mpi_ranks.sh [VOLSTREAM] [CELLS] [SIZE] [DEMO] [ENCODING] [OTHER]   (oversubscribes when ranks > cores)
#   DEMO: jet (AMR, default) or a mesh demo (tets, mixed, holes; CELLS is then its element count)
#   ENCODING: meshes, compact (default) or reference
#   OTHER: meshes, another volstream binary (e.g. main's) to compare per rank on the same dataset
#     (COUNTS 1 2 4): each binary's peak RSS per rank (/usr/bin/time -f %M) and the bytes its
#     read calls returned from the dataset's topology files (strace), ranks in one line each.
# MPIRUN (environment): the launcher, default mpirun (Open MPI); e.g. MPIRUN=mpiexec.mpich with a
#   binary built against MPICH (scripts/test_mpich.sh).
set -euo pipefail
VS="${1:-build/volstream}"
CELLS="${2:-2000000}"
SIZE="${3:-512x512}"
DEMO="${4:-jet}"
ENCODING="${5:-compact}"
OTHER="${6:-}"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN="${MPIRUN:-mpirun}"
OVERSUBSCRIBE=()  # Open MPI needs it for more ranks than cores; MPICH's Hydra does not know it
if "$MPIRUN" --version 2>&1 | grep -q "Open MPI"; then OVERSUBSCRIBE=(--oversubscribe); fi
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
  echo "== $MPIRUN ${OVERSUBSCRIBE[*]} -np $n $VS render $DEMO ${OPTIONS[*]} --size $SIZE"
  "$MPIRUN" "${OVERSUBSCRIBE[@]}" -np "$n" "$VS" render "$WORK/ds" "${OPTIONS[@]}" --size "$SIZE" -o "$WORK/$n.pfm"
  [ "$n" = 1 ] || echo "max |difference| to 1 rank: $(python3 "$TOOL" compare "$WORK/1.pfm" "$WORK/$n.pfm" 1)"
done
# Per rank: peak RSS (KiB) and topology bytes read (read syscalls on the dataset's *.bin files).
per_rank() {
  local bin="$1" n="$2" tag="$3"
  # The rank: Open MPI's variable, or the PMI one of MPICH's Hydra.
  "$MPIRUN" "${OVERSUBSCRIBE[@]}" -np "$n" bash -c 'exec /usr/bin/time -f %M -o "$0.${OMPI_COMM_WORLD_RANK:-$PMI_RANK}" "$@"' \
    "$WORK/$tag.rss" "$bin" render "$WORK/ds" "${OPTIONS[@]}" --size "$SIZE" -o "$WORK/$tag.pfm" >/dev/null
  "$MPIRUN" "${OVERSUBSCRIBE[@]}" -np "$n" bash -c \
    'exec strace -f -qq -y -e trace=read,pread64,readv,preadv,preadv2 -o "$0.${OMPI_COMM_WORLD_RANK:-$PMI_RANK}" "$@"' \
    "$WORK/$tag.trace" "$bin" render "$WORK/ds" "${OPTIONS[@]}" --size "$SIZE" -o "$WORK/$tag.pfm" >/dev/null
  python3 - "$WORK" "$tag" "$n" <<'PY'
import re, sys
work, tag, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
call = re.compile(r"\b(?:read|pread64|readv|preadv2?)\(\d+<" + re.escape(work) + r"/ds/([^/>]+\.bin)>.*\) = (\d+)$")
for r in range(n):
    rss = int(open("%s/%s.rss.%d" % (work, tag, r)).read().split()[-1])
    read = sum(int(m.group(2)) for line in open("%s/%s.trace.%d" % (work, tag, r)) if (m := call.search(line)))
    print("%s rank %d of %d: peak RSS %d KiB, topology read %d B" % (tag, r, n, rss, read))
PY
}
if [ -n "$OTHER" ]; then
  echo "topology files: $(cat "$WORK"/ds/*.bin | wc -c) B ($(cd "$WORK/ds" && ls *.bin | xargs))"
  for n in 1 2 4; do
    per_rank "$VS" "$n" this
    per_rank "$OTHER" "$n" other
  done
fi
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
