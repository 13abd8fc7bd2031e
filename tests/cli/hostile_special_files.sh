#!/usr/bin/env bash
# Class 4, special files: a FIFO or a directory where a step file, colour map or points file is
# expected. Each is refused at once (no hang, no O_DIRECT warning before the real error).
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 2 -o ds -q >/dev/null
step=$(ls ds/fields/*/step_000001.f32 | head -1)
cp -r ds fifo && rm "fifo/${step#ds/}" && mkfifo "fifo/${step#ds/}"
expect_bad_input "FIFO as step file" play fifo --pipeline direct-io --size 8x8 -q
cp -r ds dir && rm "dir/${step#ds/}" && mkdir "dir/${step#ds/}"
expect_bad_input "directory as step file" play dir --pipeline direct-io --size 8x8 -q
grep -q O_DIRECT "$WORK/err.txt" && fail "misleading O_DIRECT message: $(cat "$WORK/err.txt")"
mkfifo map.json
expect_bad_input "FIFO as colour map" render ds --tf map.json -o x.png --size 8x8
mkdir dirmap.json
expect_bad_input "directory as colour map" render ds --tf dirmap.json -o x.png --size 8x8
mkfifo points.txt
expect_bad_input "FIFO as points" probe ds --points points.txt
expect_bad_input "directory as points" probe ds --points "$WORK"
mkfifo trace.json
expect_bad_input "FIFO as trace" timeline trace.json -o t.svg
cp -r ds fifo_m && rm fifo_m/manifest.json && mkfifo fifo_m/manifest.json
expect_bad_input "FIFO as manifest" info fifo_m
