#!/usr/bin/env bash
# Truncated, inconsistent and garbage inputs of every format: one line, exit status 2.
source "$(dirname "$0")/common.bash"
cd "$WORK"

# ExaBrick: a valid pair first, then broken variants.
python3 - <<'PY'
import struct
cells = [(x, y, z, 0) for z in range(2) for y in range(2) for x in range(4)]
open("ok.cells", "wb").write(b"".join(struct.pack("<4i", *c) for c in cells))
open("ok.scalars", "wb").write(struct.pack("<%df" % len(cells), *range(len(cells))))
open("short.scalars", "wb").write(struct.pack("<3f", 1, 2, 3))
open("ragged.cells", "wb").write(open("ok.cells", "rb").read()[:-3])
dup = cells + [cells[0]]
open("dup.cells", "wb").write(b"".join(struct.pack("<4i", *c) for c in dup))
open("dup.scalars", "wb").write(struct.pack("<%df" % len(dup), *range(len(dup))))
open("overlap.cells", "wb").write(b"".join(struct.pack("<4i", *c) for c in cells + [(0, 0, 0, 1)]))
open("overlap.scalars", "wb").write(struct.pack("<%df" % (len(cells) + 1), *range(len(cells) + 1)))
open("level.cells", "wb").write(struct.pack("<4i", 0, 0, 0, 99))
open("level.scalars", "wb").write(struct.pack("<f", 1))
open("misaligned.cells", "wb").write(struct.pack("<4i", 1, 0, 0, 1))
open("misaligned.scalars", "wb").write(struct.pack("<f", 1))
open("garbage.cells", "wb").write(bytes(range(256)) * 4)
open("garbage.scalars", "wb").write(bytes(64 * 4))
open("empty.cells", "wb").write(b"")
PY
"$VS" convert ok.cells ok.scalars -o ok_ds -q >/dev/null || fail "valid ExaBrick input rejected"
expect_bad_input "scalars too short" convert ok.cells short.scalars -o x -q
expect_bad_input "ragged cells file" convert ragged.cells ok.scalars -o x -q
expect_bad_input "duplicate cell" convert dup.cells dup.scalars -o x -q
expect_bad_input "overlapping levels" convert overlap.cells overlap.scalars -o x -q
expect_bad_input "level out of range" convert level.cells level.scalars -o x -q
expect_bad_input "misaligned cell" convert misaligned.cells misaligned.scalars -o x -q
expect_bad_input "garbage cells" convert garbage.cells garbage.scalars -o x -q
expect_bad_input "empty cells" convert empty.cells ok.scalars -o x -q
expect_bad_input "missing input" convert nothere.cells ok.scalars -o x -q
expect_bad_input "unknown field to keep" convert ok.cells ok.scalars --fields nope -o x -q
expect_bad_input "unknown demo field" demo jet --cells 2e4 --steps 1 --fields nope -o x -q
"$VS" demo jet --cells 2e4 --steps 1 --fields vorticity -q -o one_field >/dev/null || fail "demo --fields rejected"
"$VS" info one_field --json | python3 -c 'import json,sys; f=json.load(sys.stdin)["fields"]; assert [x["name"] for x in f]==["vorticity"], f' \
  || fail "demo --fields vorticity did not keep exactly that field"

# Raw grids.
head -c 100 /dev/urandom >r.raw
expect_bad_input "raw size mismatch" convert r.raw --dims 4,4,4 --type float32 -o x -q
expect_bad_input "raw bad type" convert r.raw --dims 5,5,1 --type float17 -o x -q
expect_bad_input "raw without dims" convert r.raw -o x -q

# Plotfiles.
mkdir -p plt_garbage && head -c 500 /dev/urandom >plt_garbage/Header
expect_bad_input "plotfile garbage header" convert plt_garbage -o x -q --format plotfile
mkdir -p plt_text && printf 'HyperCLaw-V1.1\n1000000000\n' >plt_text/Header
expect_bad_input "plotfile absurd component count" convert plt_text -o x -q
mkdir -p not_a_plotfile
expect_bad_input "directory that is no plotfile" convert not_a_plotfile -o x -q

# Native datasets: broken manifest, truncated topology, truncated field file.
cp -r ok_ds ds1 && echo '{"format": "volstream-amr", "format_version": 1' >ds1/manifest.json
expect_bad_input "truncated manifest" info ds1
cp -r ok_ds ds2 && truncate -s 20 ds2/bricks.bin
expect_bad_input "truncated bricks" info ds2
cp -r ok_ds ds3 && truncate -s 8 ds3/fields/*/step_000000.f32
expect_bad_input "truncated field file" probe ds3 --points /dev/null
cp -r ok_ds ds4 && sed -i 's/"cell_count": 16/"cell_count": 17/' ds4/manifest.json
expect_bad_input "inconsistent cell count" info ds4
expect_bad_input "missing dataset" info does_not_exist
printf '1 2\n' >pts.txt
expect_bad_input "malformed probe point" probe ok_ds --points pts.txt
expect_bad_input "unknown field" probe ok_ds --field nope --points /dev/null
expect_bad_input "step out of range" probe ok_ds --step 5 --points /dev/null
echo "all bad inputs rejected cleanly"
