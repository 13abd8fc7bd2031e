#!/usr/bin/env bash
# The readers' cost on a 1M-tet mesh (bench/RESULTS.md, "Meshes from parallel writers and VTK's
# other compressors"): the same mesh as VTK's writer leaves it uncompressed and in each of its
# three compressors, and as volstream's demo writes it whole (.vtu) and as four pieces with ghost
# cells (.pvtu). Each file converted REPEATS times; the figures are the convert line's own
# "read" seconds (the reader, join_pieces and check_mesh) and the whole command's wall time.
# usage: measure.sh VOLSTREAM DIR [REPEATS]   (DIR: where the files are written; about 200 MB)
set -euo pipefail
VS="$1"; DIR="$2"; REPEATS="${3:-5}"
HERE="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$DIR" && cd "$DIR"
if [ ! -f t.pvtu ]; then
  "$VS" demo tets --elements 1e6 --steps 1 -o demo -q --write-mesh t.vtu --write-mesh t.pvtu
  /usr/bin/python3 "$HERE/write_vtk_compressed.py" t.vtu
fi
ls -l t*.vtu t.pvtu | awk '{ print $5, $9 }'
for f in t_none.vtu t_zlib.vtu t_lz4.vtu t_lzma.vtu t.vtu t.pvtu; do
  for r in $(seq "$REPEATS"); do
    start=$(date +%s.%N)
    line=$("$VS" convert "$f" -o "out_$f" --encoding reference 2>&1 | tail -1)
    end=$(date +%s.%N)
    read_s=$(echo "$line" | sed -n 's/.*(read \([0-9.]*\)s.*/\1/p')
    printf '%s round %d: read %s s, whole %.2f s\n' "$f" "$r" "$read_s" "$(echo "$end - $start" | bc)"
  done
done
