#!/usr/bin/env bash
# render: the built-in demo and a dataset to PNG/PFM with the main options; bad options exit 2.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 100000 --steps 2 -o jet -q
out=$("$VS" render jet --step 1 --size 96x64 -o a.png)
echo "$out" | grep -qE '^device: (cpu|cuda)' || fail "render does not report the device: $out"
echo "$out" | grep -q 'M samples/s' || fail "render does not report samples/s: $out"
[ "$(head -c 4 a.png | tail -c 3)" = PNG ] || fail "a.png is not a PNG"
"$VS" render jet --field pressure --tf cool-warm --range -3000,1000 --opacity -3000:0.2,0:0,1000:0.2 \
  --iso -500 --color-field velocity --shade --ortho --spp 2 --rate 1 --size 64x48 --alpha -o b.pfm >/dev/null
[ -f b.pfm ] && [ -f b.alpha.pfm ] || fail "PFM with alpha not written"
cat >cm.json <<'JSON'
[{"Name": "test", "RGBPoints": [0, 0, 0, 1, 1, 1, 0, 0], "Points": [0, 0, 0.5, 0, 1, 0.5, 0.5, 0]}]
JSON
"$VS" render jet --field velocity --tf cm.json --camera-pos 0,30,40 --camera-at 5,0,0 --fov 30 --no-skip \
  --no-adaptive --background 1,1,1 --size 48x48 -o c.png >/dev/null
"$VS" render --demo cosmo --cells 20000 --log --size 48x48 -o d.png | grep -q 'field density' || fail "cosmo demo"
expect_bad_input "no input" render -o x.png
expect_bad_input "bad size" render jet --size 0x10 -o x.png
expect_bad_input "bad extension" render jet -o x.jpg
expect_bad_input "bad colour map" render jet --tf nosuchmap -o x.png
expect_bad_input "bad opacity" render jet --opacity 3 -o x.png
# --layers N[:ALPHA]: the opacity of bench/layers_opacity.py (yt's add_layers), as an option.
"$VS" render jet --log --range 1,1600 --layers 6 --size 48x48 -o layers.pfm >/dev/null
"$VS" render jet --log --range 1,1600 --opacity "$(/usr/bin/python3 "$(dirname "$0")/../../bench/layers_opacity.py" 1 1600 6 0.3)" \
  --size 48x48 -o points.pfm >/dev/null
/usr/bin/python3 - layers.pfm points.pfm <<'PY' || fail "--layers 6 differs from the same layers as --opacity points"
import struct, sys
def pfm(path):
    with open(path, "rb") as f:
        f.readline(); w, h = map(int, f.readline().split()); f.readline()
        data = f.read()
        return struct.unpack("<%df" % (len(data) // 4), data)
a, b = pfm(sys.argv[1]), pfm(sys.argv[2])
assert max(abs(x - y) for x, y in zip(a, b)) < 1e-3 and max(a) > 1e-3, (max(a), max(abs(x - y) for x, y in zip(a, b)))
PY
expect_bad_input "layers and opacity" render jet --layers 6 --opacity 1:0.5 -o x.png
expect_bad_input "bad layer count" render jet --layers 0 -o x.png
expect_bad_input "bad layer alpha" render jet --layers 4:2 -o x.png
expect_bad_input "bad camera" render jet --camera-pos 1,2 -o x.png
expect_bad_input "degenerate camera" render jet --camera-pos 1,1,1 --camera-at 1,1,1 -o x.png
expect_bad_input "unknown field" render jet --field nope -o x.png
expect_bad_input "bad step" render jet --step 9 -o x.png
expect_bad_input "bad device" render jet --device gpu -o x.png
expect_bad_input "broken colour map file" render jet --tf cm_missing.json -o x.png
echo '[{"RGBPoints": [0, 1]}]' >bad.json
expect_bad_input "malformed colour map" render jet --tf bad.json -o x.png
echo "ok: render"
