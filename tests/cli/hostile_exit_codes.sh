#!/usr/bin/env bash
# Class 7, exit codes: every refusal is one line and exit 2; probe keeps one output line per point.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 1 -o ds -q >/dev/null
expect_bad_input "missing output directory" render ds -o nowhere/x.png --size 8x8
expect_bad_input "missing output directory (play)" play ds -o nowhere/f_%d.png --size 8x8 -q
expect_bad_input "missing output directory (timeline trace)" play ds --timeline nowhere/t.json --size 8x8 -q
mkdir bin && for c in bash timeout head wc grep cat; do ln -s "$(command -v $c)" bin/$c; done
PATH="$WORK/bin" expect_bad_input "ffmpeg not on PATH" play ds -o v.mp4 --size 8x8 -q
[ ! -e v.mp4 ] || fail "v.mp4 exists"
expect_bad_input "malformed --opacity" render ds --opacity 5: -o x.png --size 8x8
expect_bad_input "malformed --opacity (no value)" render ds --opacity :0.5 -o x.png --size 8x8
cp -r ds empty && /usr/bin/python3 - empty/manifest.json <<'PY'
import json, sys
m = json.load(open(sys.argv[1])); m["cell_count"] = 0; m["levels"] = []; json.dump(m, open(sys.argv[1], "w"))
PY
expect_bad_input "info on a zero-cell dataset" info empty
printf '0 0 0\nnan nan nan\n\n1 1 1\ninf 0 0\n' | "$VS" probe ds >p.txt || fail "probe failed"
[ "$(wc -l <p.txt)" = 4 ] || fail "probe dropped lines: $(cat p.txt)"
[ "$(sed -n 2p p.txt)" = nan ] || fail "nan point: $(cat p.txt)"
echo "ok: probe keeps one line per point"
expect_bad_input "directory as points file" probe ds --points ds
