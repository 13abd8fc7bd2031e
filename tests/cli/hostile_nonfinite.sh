#!/usr/bin/env bash
# Class 1, non-finite numbers: NaN boxes in a topology file, infinite values or values beyond
# float range, bad spacing. NaN values are kept as "no data" (docs/formats.md); nothing the
# reader rejects is ever written.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 1 -o ds -q >/dev/null
# poke FILE OFFSET HEX: overwrite bytes in place.
poke() { printf "$3" | dd of="$1" bs=1 seek="$2" conv=notrunc status=none; }
raw() { /usr/bin/python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<$1', *[$2]))" >"$3"; }

cp -r ds nan_box && poke nan_box/abrs.bin 0 '\x00\x00\xc0\x7f'
expect_bad_input "NaN in an ABR box" render nan_box -o x.png --size 16x16
cp -r ds inf_box && poke inf_box/abrs.bin 16 '\x00\x00\x80\x7f'
expect_bad_input "Inf in an ABR box" probe inf_box </dev/null

raw 8d "1,2,3,4,5,6,7,1e39" big.raw
expect_bad_input "float64 beyond float range" convert big.raw --dims 2,2,2 --type float64 -o big_ds
[ ! -e big_ds ] || fail "a failed convert left big_ds behind"
raw 8f "1,2,3,4,5,6,7,float('inf')" inf.raw
expect_bad_input "infinite value" convert inf.raw --dims 2,2,2 -o inf_ds
raw 8f "float('nan')]*8+[" allnan.raw
expect_bad_input "no finite value" convert allnan.raw --dims 2,2,2 -o allnan_ds

# NaN values are "no data": converted, readable, finite ranges, probed as nan.
raw 8f "1,2,3,4,5,6,7,float('nan')" nan.raw
"$VS" convert nan.raw --dims 2,2,2 -o nan_ds -q >/dev/null || fail "NaN values refused"
"$VS" info nan_ds --json | grep -q '"max": 7' || fail "range of NaN data is not over the finite values"
printf '1.5 1.5 1.5\n0.5 0.5 0.5\n' | "$VS" probe nan_ds >probe.txt || fail "probe failed"
[ "$(sed -n 2p probe.txt)" = 1 ] || fail "probe: $(cat probe.txt)"
echo "ok: NaN values kept as no data"

raw 8f "1,2,3,4,5,6,7,8" ok.raw
for s in 0,1,1 -1,1,1 1,1e-30,1 1,1,1e300; do
  expect_bad_input "spacing $s" convert ok.raw --dims 2,2,2 --spacing "$s" -o sp_ds
done
expect_bad_input "origin 1e300" convert ok.raw --dims 2,2,2 --origin 1e300,0,0 -o sp_ds
[ ! -e sp_ds ] || fail "a refused convert left sp_ds behind"

# Non-finite or out-of-float-range render lengths are refused, not rendered as empty or opaque.
for unit in inf nan 1e50 1e-50 -1; do
  expect_bad_input "--unit-distance $unit" render ds -o x.png --size 16x16 --unit-distance "$unit"
done
