#!/usr/bin/env bash
# render, play and bench stream share one set of render options (apps/render_options.h): the same
# options give play the frame render draws; play and bench accept every option that can stream
# and reject the others with one line; play's own defaults stay (256x256, the first field).
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 3 -o ds -q >/dev/null

# Every shared option at once (an explicit --range: render's default is one step's range, a
# stream's the union over all steps): play's frame is render's image, byte for byte.
O=(--field vorticity --tf auto --range 1,700 --log --opacity 5:0,700:0.3 --iso 30 --iso-alpha 0.7 --spp 2
   --ortho --shade --no-jitter --no-adaptive --rate 1.5 --unit-distance 0.5 --device cpu
   --background 1,1,1 --camera-up 0,0,1 --fov 40 --no-skip)
"$VS" render ds --step 1 "${O[@]}" --size 48x32 -o r.png >/dev/null
"$VS" play ds --steps 1 "${O[@]}" --size 48x32 -o "p_%d.png" -q >/dev/null
cmp -s r.png p_0.png || fail "play with the shared options does not draw render's image"
"$VS" render ds --step 1 --field vorticity --tf auto --range 1,700 --log --size 48x32 -o plain.png >/dev/null
cmp -s r.png plain.png && fail "the shared options had no effect"
echo "ok: play draws render's image with all shared options"

# Isosurfaces and an orthographic camera change play's frames (not silently ignored).
"$VS" play ds --steps 0 --size 48x32 -o "a_%d.png" -q >/dev/null
"$VS" play ds --steps 0 --size 48x32 --iso 0 -o "b_%d.png" -q >/dev/null
"$VS" play ds --steps 0 --size 48x32 --ortho -o "c_%d.png" -q >/dev/null
cmp -s a_0.png b_0.png && fail "play --iso did not change the frame"
cmp -s a_0.png c_0.png && fail "play --ortho did not change the frame"
echo "ok: play --iso, --ortho"

# bench stream takes them too, and its levels still agree.
"$VS" bench stream ds --steps 0:3 --levels baseline,refit,overlap "${O[@]}" --size 32x24 >bench.txt 2>/dev/null \
  || fail "bench stream with the shared options failed: $(cat bench.txt)"
grep -q "frames identical at every level: yes" bench.txt || fail "bench: $(cat bench.txt)"
grep -q "field vorticity, 3 frames, 32x24 on cpu" bench.txt || fail "bench ignored --field/--size: $(head -1 bench.txt)"
echo "ok: bench stream with the shared options"

# Defaults: play and bench keep theirs (256x256, the first field, cpu), render its own.
"$VS" play ds --steps 0 -o "d_%d.png" -q >/dev/null
python3 - d_0.png <<'PY' || fail "play's default size is not 256x256"
import struct, sys
w, h = struct.unpack(">II", open(sys.argv[1], "rb").read()[16:24])
assert (w, h) == (256, 256), (w, h)
PY
"$VS" bench stream ds --steps 0 --levels baseline 2>/dev/null | grep -q "field pressure, 1 frames, 256x256 on cpu" \
  || fail "bench stream's defaults changed"
# The help is captured first: grep -q stops reading at its match, and under pipefail the
# writer's SIGPIPE would fail the pipeline when the help is long.
play_help=$("$VS" play --help)
render_help=$("$VS" render --help)
grep -q -- "--size TEXT=256x256" <<<"$play_help" || fail "play --help: size default"
grep -q -- "--size TEXT=512x512" <<<"$render_help" || fail "render --help: size default"
grep -q -- "--device TEXT=auto" <<<"$render_help" || fail "render --help: device default"
echo "ok: defaults"

# What cannot stream is refused with one line, never silently ignored; bad values as in render.
for cmd in "play" "bench stream"; do
  # shellcheck disable=SC2086
  expect_bad_input "$cmd --color-field" $cmd ds --color-field velocity --iso 0
  expect_bad_input "$cmd --stored-ranges" $cmd ds --stored-ranges
  expect_bad_input "$cmd --alpha" $cmd ds --alpha
  expect_bad_input "$cmd --spp 0" $cmd ds --spp 0
  expect_bad_input "$cmd bad --iso" $cmd ds --iso 1,x
  expect_bad_input "$cmd bad --opacity" $cmd ds --opacity 3
  expect_bad_input "$cmd --iso-alpha 2" $cmd ds --iso-alpha 2
  expect_bad_input "$cmd degenerate camera" $cmd ds --camera-pos 1,1,1 --camera-at 1,1,1
  expect_bad_input "$cmd unknown field" $cmd ds --field nope
  expect_bad_input "$cmd bad device" $cmd ds --device gpu
done
echo "all shared render option tests passed"
