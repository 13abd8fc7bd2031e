#!/usr/bin/env bash
# mpirun -np N volstream render (issue 17): the images of 1, 2, 3, 4 and 8 ranks agree within
# 1e-5 (float PFM) for random cameras inside and outside the domain, on a demo and a plotfile,
# with isosurfaces and shading, and those of 1 to 4 ranks on a small mesh demo in both encodings
# (a shaded isosurface in both, volume light in the compact one); the ranks' regions hold every
# cell (mesh element) once and each rank reads exactly its held bricks' (vertices') values; a
# bad input ends every rank with one line and status 2; a rank reads less topology at 4 ranks
# than at 1 (AMR) or than the whole (meshes); mpirun play writes the frames of one rank with any
# count (AMR and a mesh), and a trace with every rank's stages, composite included.
# Usage: render_ranks.sh VOLSTREAM MPIEXEC WORKDIR (oversubscribed: CI has 2 cores).
set -euo pipefail
VS="$1"
MPIRUN="$2"
WORK="$3"
HERE="$(cd "$(dirname "$0")" && pwd)"
TOOL="$HERE/mpi_tool.py"
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK"
# Open MPI refuses root and more ranks than cores unless told; MPICH's Hydra allows both and
# knows no --oversubscribe.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
OVERSUBSCRIBE=()
if "$MPIRUN" --version 2>&1 | grep -q "Open MPI"; then OVERSUBSCRIBE=(--oversubscribe); fi
fail() { echo "FAIL: $*" >&2; exit 1; }
ranks() { local n="$1"; shift; timeout 120 "$MPIRUN" "${OVERSUBSCRIBE[@]}" -np "$n" "$VS" "$@" </dev/null; }

"$VS" demo jet --cells 20000 --steps 1 -o jet -q
python3 "$HERE/../golden/make_plotfile.py" plt >/dev/null
"$VS" convert plt -o pltds -q
# The mesh with a cavity and two parts (rays leave and re-enter it), in both encodings.
"$VS" demo holes --elements 3000 --steps 1 -o holes_c -q
"$VS" demo holes --elements 3000 --steps 1 --encoding reference -o holes_r -q

# dataset, camera count, seed, render options; the rank counts besides 1 are $COUNTS.
COUNTS="2 3 4 8"
check_dataset() {
  local ds="$1" count="$2" seed="$3"; shift 3
  "$VS" info "$ds" --json >"$ds.json"
  local cells  # or a mesh's elements
  cells=$(python3 -c "import json,sys; j = json.load(open(sys.argv[1])); print(j['elements'] if j.get('kind') == 'umesh' else j['cells'])" "$ds.json")
  python3 "$TOOL" cameras "$ds.json" "$count" "$seed" >"$ds.cameras"
  local c=0
  while read -r -a camera; do
    c=$((c + 1))
    ranks 1 render "$ds" "${camera[@]}" "$@" --size 40x32 -o "$ds.$c.1.pfm" >"$ds.$c.1.log"
    # One process without mpirun stops rays at 99 % opacity; the ranks never do.
    "$VS" render "$ds" "${camera[@]}" "$@" --size 40x32 -o "$ds.$c.plain.pfm" >/dev/null
    echo "$ds camera $c: plain vs 1 rank $(python3 "$TOOL" compare "$ds.$c.plain.pfm" "$ds.$c.1.pfm" 0.02)" ||
      fail "$ds camera $c: one process and one rank differ"
    for n in $COUNTS; do
      ranks "$n" render "$ds" "${camera[@]}" "$@" --size 40x32 -o "$ds.$c.$n.pfm" >"$ds.$c.$n.log" ||
        fail "$ds camera $c: $n ranks failed"
      diff=$(python3 "$TOOL" compare "$ds.$c.1.pfm" "$ds.$c.$n.pfm" 1e-5) ||
        fail "$ds camera $c (${camera[*]}): $n ranks differ from 1 by $diff"
      ghosts=$(python3 "$TOOL" ranks "$ds.$c.$n.log" 1 "$cells") || fail "$ds camera $c, $n ranks: $ghosts"
      echo "$ds camera $c: $n ranks, max diff $diff, $ghosts"
    done
  done <"$ds.cameras"
}
check_dataset jet 3 7 --field pressure --iso -500 --shade
check_dataset pltds 2 3 --field density --iso 0.6 --range 0,1.4
# Meshes: volume light in the compact encoding, a shaded isosurface (look-back and gradients
# across the boxes) in both; each with a camera inside and one outside.
COUNTS="2 3 4"
check_dataset holes_c 2 5 --field density
check_dataset holes_c 2 11 --field density --iso 0.3 --shade
check_dataset holes_r 2 11 --field density --iso 0.3 --shade
COUNTS="2 3 4 8"
# Each rank reads its share of a mesh's topology (the index, then its items), in both encodings.
for encoding in compact reference; do
  ds="tets_$encoding"
  "$VS" demo tets --elements 20000 --steps 1 --encoding "$encoding" -o "$ds" -q
  whole=$(cat "$ds"/*.bin | wc -c)
  ranks 1 render "$ds" --field density --size 40x32 -o "$ds.1.pfm" >/dev/null
  ranks 4 render "$ds" --field density --size 40x32 -o "$ds.4.pfm" >"$ds.4.log"
  python3 "$TOOL" compare "$ds.1.pfm" "$ds.4.pfm" 1e-5 >/dev/null || fail "$ds: 4 ranks differ from 1"
  python3 "$TOOL" ranks "$ds.4.log" 1 "$(python3 -c "import json; print(json.load(open('$ds/manifest.json'))['element_count'])")" \
    >/dev/null || fail "$ds: owned elements or values read"
  echo "$ds, 4 ranks: $(python3 "$TOOL" topology "$ds.4.log" "$whole")" || fail "$ds: a rank read the whole topology"
done
# An AMR rank reads the bricks and the ABR chunk index, then only its chunks' ABRs and lists:
# less than the whole topology (abr_bvh.bin is never read), and less at 4 ranks than at 1.
whole=$(cat jet/abr*.bin jet/bricks.bin | wc -c)
one=$(python3 "$TOOL" topology jet.1.1.log "$whole" | sed -nE 's/.* to ([0-9]+) B .*/\1/p') ||
  fail "jet, 1 rank: it read the whole topology"
echo "jet, 4 ranks: $(python3 "$TOOL" topology jet.1.4.log "$one")" || fail "jet: 4 ranks read no less than 1"
# Direct send for a power-of-two count gives the binary swap's image.
ranks 4 render jet --composite direct-send --size 40x32 -o direct.pfm >/dev/null
ranks 4 render jet --composite binary-swap --size 40x32 -o swap.pfm >/dev/null
python3 "$TOOL" compare direct.pfm swap.pfm 1e-5 >/dev/null || fail "direct send and binary swap differ"

# A bad input on the ranks: one line from rank 0 (mpirun adds its own notes), status 2.
expect_bad_ranks() {
  local what="$1"; shift
  local status=0
  ranks 3 "$@" >out.txt 2>err.txt || status=$?
  [ "$status" = 2 ] || fail "$what: status $status (stderr: $(head -c 300 err.txt))"
  [ "$(grep -c '^volstream: ' err.txt)" = 1 ] || fail "$what: expected one volstream line: $(cat err.txt)"
  echo "ok: $what -> $(grep '^volstream: ' err.txt)"
}
cp -r jet broken
truncate -s 100 broken/fields/0_pressure/step_000000.f32
expect_bad_ranks "truncated values" render broken --field pressure -o x.png --size 16x16
# A damaged ABR chunk index: refused at open by every rank, or (chunk 0 finer than its ABRs) by
# the ranks that read chunk 0.
cp -r jet broken_chunks
truncate -s 100 broken_chunks/abr_chunks.bin
expect_bad_ranks "ABR chunk index truncated" render broken_chunks -o x.png --size 16x16
cp -r jet finer_chunk
python3 -c "import struct, sys; f = open(sys.argv[1], 'r+b'); f.seek(24); f.write(struct.pack('<f', 0.5))" \
  finer_chunk/abr_chunks.bin
expect_bad_ranks "ABR chunk finer than its ABRs" render finer_chunk -o x.png --size 16x16
expect_bad_ranks "unknown field" render jet --field nope -o x.png
expect_bad_ranks "blocks integrator" render jet --integrator blocks -o x.png
expect_bad_ranks "several rays a pixel" render jet --spp 2 -o x.png
# Orthographic, a colour field (two fields read), no skipping, stored ranges: still one image.
for n in 1 3; do
  ranks "$n" render jet --field pressure --iso -500 --color-field velocity --ortho --rate 1 --size 40x32 \
    -o ortho.$n.pfm >ortho.$n.log
  ranks "$n" render jet --no-skip --no-adaptive --stored-ranges --camera-pos 300,40,-100 --size 40x32 \
    -o plain.$n.pfm >/dev/null
done
python3 "$TOOL" compare ortho.1.pfm ortho.3.pfm 1e-5 >/dev/null || fail "ortho + colour field: 3 ranks differ"
python3 "$TOOL" ranks ortho.3.log 2 "$(python3 -c "import json; print(json.load(open('jet.json'))['cells'])")" \
  >/dev/null || fail "ortho + colour field: bytes read"
python3 "$TOOL" compare plain.1.pfm plain.3.pfm 1e-5 >/dev/null || fail "no skipping, stored ranges: 3 ranks differ"
cp -r holes_r broken_mesh
truncate -s 100 broken_mesh/fields/0_density/step_000000.f32
expect_bad_ranks "mesh: truncated values" render broken_mesh --field density -o x.png --size 16x16

# play: every frame of 2 and 3 ranks as 1 rank's (PNG: within one 8-bit code, the rounding of
# float differences up to 1e-5); the trace has every rank's stages with the composite.
"$VS" demo jet --cells 20000 --steps 3 -o series -q
for n in 1 2 3; do
  mkdir -p play$n
  ranks "$n" play series --field vorticity --log --size 48x40 -o "play$n/f_%04d.png" --timeline "play$n.json" -q \
    >"play$n.log" || fail "play on $n ranks failed"
  grep -q "^played 3 frames on $n ranks" "play$n.log" || fail "play on $n ranks: $(cat "play$n.log")"
done
for n in 2 3; do
  for f in 0000 0001 0002; do
    max=$(python3 "$HERE/../../bench/png_compare.py" "play1/f_$f.png" "play$n/f_$f.png" | sed -nE 's/.* max ([0-9]+) .*/\1/p')
    [ "${max:-99}" -le 1 ] || fail "play frame $f: $n ranks differ from 1 by $max codes"
  done
done
python3 - play3.json <<'PY' || fail "play trace"
import json, sys
events = [e for e in json.load(open(sys.argv[1]))["traceEvents"] if e["ph"] == "X"]
for pid in (1, 2, 3):
    names = {e["name"] for e in events if e["pid"] == pid}
    assert {"read", "ranges", "render", "composite"} <= names, (pid, names)
    assert sum(e["name"] == "composite" for e in events if e["pid"] == pid) == 3, pid
assert {e["name"] for e in events if e["name"] == "output"} and all(e["pid"] == 1 for e in events if e["name"] == "output")
PY
# A mesh series: every frame of 3 ranks is 1 rank's (each rank reads its vertices' values per step).
"$VS" demo tets --elements 2000 --steps 2 -o mesh_series -q
for n in 1 3; do
  mkdir -p mesh_play$n
  ranks "$n" play mesh_series --field density --size 48x40 -o "mesh_play$n/f_%04d.png" -q >/dev/null ||
    fail "mesh play on $n ranks failed"
done
for f in 0000 0001; do
  max=$(python3 "$HERE/../../bench/png_compare.py" "mesh_play1/f_$f.png" "mesh_play3/f_$f.png" | sed -nE 's/.* max ([0-9]+) .*/\1/p')
  [ "${max:-99}" -le 1 ] || fail "mesh play frame $f: 3 ranks differ from 1 by $max codes"
done
cp -r series broken_series
truncate -s 100 broken_series/fields/0_pressure/step_000001.f32
expect_bad_ranks "play: truncated values of step 1" play broken_series --field pressure -o "bad_%04d.png" -q
echo "all ranks agree"
