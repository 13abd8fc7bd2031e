#!/usr/bin/env bash
# Class 3, degenerate geometry: an ABR stretched far beyond its bricks, tiny or huge cells. The
# reader refuses them so that render and play never see them (and never run for minutes).
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 2 -o ds -q >/dev/null
poke() { printf "$3" | dd of="$1" bs=1 seek="$2" conv=notrunc status=none; }
cp -r ds long && poke long/abrs.bin 12 '\x00\x24\x74\x49'  # upper.x = 1e6
expect_bad_input "ABR stretched to 1e6" render long -o x.png --size 16x16
cp -r ds inverted && poke inverted/abrs.bin 12 '\x00\x00\x10\xc1'  # upper.x = -9 < lower.x
expect_bad_input "inverted ABR" play inverted --size 8x8 -q
cp -r ds width && poke width/abrs.bin 32 '\x00\x00\x80\x3e'  # finest_width = 0.25
expect_bad_input "ABR finer than its bricks" render width -o x.png --size 16x16
# The ABR BVH stored at convert (8 bytes a node: child or item, is_leaf): damaged, it is refused
# (a cycle would otherwise hang traversal or overflow its stack); missing, it is built at load.
cp -r ds cycle && poke cycle/abr_bvh.bin 0 '\x00\x00\x00\x00'  # the root is its own child
expect_bad_input "ABR BVH with a cycle" render cycle -o x.png --size 16x16
cp -r ds flag && poke flag/abr_bvh.bin 4 '\x07\x00\x00\x00'  # root neither leaf nor inner
expect_bad_input "ABR BVH node flag 7" probe flag --points <(echo 1,1,1)
cp -r ds short && truncate -s -8 short/abr_bvh.bin
expect_bad_input "ABR BVH cut short" render short -o x.png --size 16x16
cp -r ds unstored && rm unstored/abr_bvh.bin && /usr/bin/python3 - unstored/manifest.json <<'PY'
import json, sys
m = json.load(open(sys.argv[1])); del m["abr_bvh_node_count"]; json.dump(m, open(sys.argv[1], "w"))
PY
"$VS" render ds -o stored.pfm --size 32x32 >/dev/null && "$VS" render unstored -o unstored.pfm --size 32x32 >/dev/null
cmp -s stored.pfm unstored.pfm || fail "a dataset without its stored BVH renders differently"
echo "ok: damaged ABR BVHs refused, a missing one built at load"
/usr/bin/python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<8f', *range(8)))" >g.raw
expect_bad_input "cells of 1e-25" convert g.raw --dims 2,2,2 --spacing 1e-25,1e-25,1e-25 -o tiny
# A manifest edited to the same effect is refused by the reader.
cp -r ds tiny_m && /usr/bin/python3 - tiny_m/manifest.json <<'PY'
import json, sys
m = json.load(open(sys.argv[1])); m["transform"]["cell_size"] = [1e-25] * 3; json.dump(m, open(sys.argv[1], "w"))
PY
expect_bad_input "manifest with cells of 1e-25" render tiny_m -o x.png --size 16x16

# A compact mesh whose first vertex-table entries are zeroed: its first elements collapse to a
# point (size 0). Their macrocells' step was 0, and an 8x8 render took 16.7 M samples per ray and
# macrocell (found by compact_dataset_fuzz); steps are now at least 1/1000 of a macrocell.
"$VS" demo mixed --elements 200 --steps 1 --encoding compact -o mesh -q >/dev/null
/usr/bin/python3 -c 'f = open("mesh/compact_bytes.bin", "r+b"); f.write(bytes(9))'
status=0
timeout 60 "$VS" render mesh -o mesh.png --size 8x8 >/dev/null 2>err.txt || status=$?
[ "$status" = 0 ] || [ "$status" = 2 ] || fail "collapsed mesh elements: render exit status $status $(cat err.txt)"
echo "ok: collapsed mesh elements render in bounded time (exit status $status)"
