#!/usr/bin/env bash
# --file-order: demo and convert also write every step in source order (padded like the
# device-order file) and file_index.bin once; the file-order copy is the device-order file
# permuted (for ExaBrick input: the scalar file as given); the manifest and info say so; every
# pipeline level plays the frames of the dataset made without it; a damaged file-order step stops
# the flattening levels (before preordered) with one line naming the step and file, while the
# later levels, which read the device-order files, play on.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 3 -o plain -q >/dev/null
"$VS" demo jet --cells 10000 --steps 3 --file-order -o fo -q >demo.txt
grep -q "file-order copies" demo.txt || fail "demo does not report the file-order copies: $(cat demo.txt)"
grep -q '"file_order": true' fo/manifest.json || fail "manifest of fo does not record file_order"
grep -q '"file_order": false' plain/manifest.json || fail "manifest of plain does not record file_order: false"
[ ! -e plain/file_index.bin ] || fail "plain dataset has a file index"
[ -z "$(find plain -name '*.file_order.f32')" ] || fail "plain dataset has file-order copies"
"$VS" info fo | grep -q "^file order yes" || fail "info does not show the file-order copies"
if "$VS" info plain | grep -q "^file order"; then fail "info shows file-order copies for plain"; fi

# Brute force: the index is a permutation (not the identity), cells.bin is the generator's cells
# permuted, the device-order files are those of plain, and file-order[index[i]] == device[i].
python3 - fo plain <<'PY' || fail "file-order files are not the device-order files permuted"
import array, glob, json, os, sys
fo, plain = sys.argv[1], sys.argv[2]
m = json.load(open(fo + "/manifest.json"))
n = m["cell_count"]
idx = array.array("I"); idx.frombytes(open(fo + "/file_index.bin", "rb").read())
assert len(idx) == n, (len(idx), n)
assert sorted(idx) == list(range(n)), "not a permutation"
moved = sum(1 for i in range(n) if idx[i] != i)
assert moved > n // 2, "almost the identity: %d of %d move" % (moved, n)
files = 0
for f in m["fields"]:
    for s in range(len(m["step_times"])):
        base = "%s/fields/%s/step_%06d" % (fo, f["dir"], s)
        dev_bytes = open(base + ".f32", "rb").read()
        assert dev_bytes == open("%s/fields/%s/step_%06d.f32" % (plain, f["dir"], s), "rb").read()
        fo_bytes = open(base + ".file_order.f32", "rb").read()
        assert len(fo_bytes) == len(dev_bytes) == (n * 4 + 4095) // 4096 * 4096, (len(fo_bytes), len(dev_bytes))
        assert fo_bytes[n * 4:] == bytes(len(fo_bytes) - n * 4), "padding is not zero"
        dev = array.array("I"); dev.frombytes(dev_bytes[:n * 4])   # bits, so NaNs compare too
        fil = array.array("I"); fil.frombytes(fo_bytes[:n * 4])
        assert all(dev[i] == fil[idx[i]] for i in range(n)), base
        assert dev != fil, "file order equals device order"
        files += 1
print("ok: %d file-order files = device-order files permuted, %d of %d cells move" % (files, moved, n))
PY

# Every level plays the frames of the dataset written without file order.
R=(--size 48x32 -q)
mkdir -p ref && "$VS" play plain --steps 0:3 --pipeline baseline -o "ref/f_%d.png" "${R[@]}" >/dev/null
for level in baseline async-io pinned direct-io preordered refit overlap; do
  rm -rf out && mkdir out
  "$VS" play fo --steps 0:3 --pipeline $level -o "out/f_%d.png" "${R[@]}" >/dev/null
  for i in 0 1 2; do cmp -s ref/f_$i.png out/f_$i.png || fail "$level frame $i differs from the device-order dataset"; done
done
echo "ok: 7 levels x 3 frames equal those of the dataset without file order"

# A damaged file-order step: the flattening levels stop before its frame, naming it.
g=$(ls fo/fields/0_*/step_000002.file_order.f32)
for damage in missing truncated oversized; do
  rm -rf bad && cp -r fo bad && h="bad/${g#fo/}"
  case $damage in
    missing) rm "$h"; word="missing" ;;
    truncated) truncate -s 1000 "$h"; word="truncated" ;;
    oversized) truncate -s +8192 "$h"; word="wrong size" ;;
  esac
  for level in baseline async-io direct-io; do
    rm -rf out && mkdir out
    expect_bad_input "$damage file-order step at $level" play bad --pipeline $level -o "out/f_%d.png" "${R[@]}"
    grep -q "step_000002.file_order.f32: step 2: .*$word" "$WORK/err.txt" || fail "error does not name the file and step 2"
    [ -f out/f_1.png ] && [ ! -e out/f_2.png ] || fail "$damage at $level: wrong frames written: $(ls out)"
  done
  rm -rf out && mkdir out
  "$VS" play bad --pipeline preordered -o "out/f_%d.png" "${R[@]}" >/dev/null || fail "preordered needs the file-order copy"
  cmp -s ref/f_2.png out/f_2.png || fail "preordered frame 2 differs"
done

# convert --file-order: the file-order copy of ExaBrick input is the scalar file as it was given.
python3 - <<'PY'
import struct, math
cells = [(x, y, z, 0) for z in range(8) for y in range(8) for x in range(8)]
cells += [(x, y, z, 1) for z in range(0, 8, 2) for y in range(0, 8, 2) for x in range(8, 16, 2)]
cells = cells[::-1]
open("a.cells", "wb").write(b"".join(struct.pack("<4i", *c) for c in cells))
open("density.scalars", "wb").write(struct.pack("<%df" % len(cells), *[math.sin(0.3 * c[0]) + 0.1 * c[1] + c[3] for c in cells]))
PY
"$VS" convert a.cells density.scalars --file-order -o exa -q >/dev/null
python3 - <<'PY' || fail "convert --file-order: the file-order copy is not the input"
import array
n = 576
given = open("density.scalars", "rb").read()
fo = open("exa/fields/0_density/step_000000.file_order.f32", "rb").read()
assert len(fo) == 4096 and fo[:n * 4] == given, len(fo)
idx = array.array("I"); idx.frombytes(open("exa/file_index.bin", "rb").read())
cells_in = open("a.cells", "rb").read(); cells_dev = open("exa/cells.bin", "rb").read()
assert all(cells_dev[16 * i:16 * i + 16] == cells_in[16 * idx[i]:16 * idx[i] + 16] for i in range(n))
dev = open("exa/fields/0_density/step_000000.f32", "rb").read()
assert all(dev[4 * i:4 * i + 4] == given[4 * idx[i]:4 * idx[i] + 4] for i in range(n))
PY
"$VS" convert a.cells density.scalars -o exa_plain -q >/dev/null
printf '2.5 3.5 4.5\n9 5 5\n' | "$VS" probe exa >p1.txt
printf '2.5 3.5 4.5\n9 5 5\n' | "$VS" probe exa_plain >p2.txt
cmp -s p1.txt p2.txt || fail "probe differs with file-order copies"
echo "ok: convert --file-order"

# bench stream over the file-order dataset: the same frames at every level.
"$VS" bench stream fo --size 32x24 >bench.txt 2>/dev/null || fail "bench stream failed: $(cat bench.txt)"
grep -q "frames identical at every level: yes" bench.txt || fail "bench: $(cat bench.txt)"
echo "file order passed"
