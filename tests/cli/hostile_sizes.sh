#!/usr/bin/env bash
# Class 2, sizes a file claims: text inputs are capped and checked to be regular files before
# they are read (/dev/zero is neither), a trace with extreme timestamps or very many distinct
# names ends quickly.
source "$(dirname "$0")/common.bash"
TESTS="$(cd "$(dirname "$0")/.." && pwd)"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 1 -o ds -q >/dev/null
ln -s /dev/zero zero.json
expect_bad_input "--tf /dev/zero" render ds --tf zero.json -o x.png --size 8x8
expect_bad_input "--points /dev/zero" probe ds --points /dev/zero
status=0; (timeout 60 "$VS" probe ds </dev/zero >/dev/null 2>err.txt) || status=$?
[ "$status" = 2 ] && grep -q "more than 256 MiB" err.txt || fail "points from /dev/zero on stdin: status $status, $(cat err.txt)"
echo '{"traceEvents":[{"ph":"X","name":"read","ts":0,"dur":1},{"ph":"X","name":"read","ts":1e300,"dur":1}]}' >extreme.json
expect_bad_input "extreme timestamps" timeline extreme.json -o t.svg
echo '{"traceEvents":[{"ph":"X","name":"read","ts":-1e15,"dur":1e15},{"ph":"X","name":"read","ts":1e15,"dur":1}]}' >far.json
"$VS" timeline far.json -o far.svg >/dev/null || fail "timeline with far timestamps did not finish"
/usr/bin/python3 -c "
import json
print(json.dumps({'traceEvents': [{'ph': 'X', 'name': 's%d' % i, 'ts': i, 'dur': 1} for i in range(100000)]}))" >names.json
timeout 60 "$VS" timeline names.json -o names.svg >/dev/null || fail "100k distinct stage names took too long"
expect_bad_input "100k stage rows" timeline names.json --rows stage -o rows.svg
echo "ok: traces with extreme values end quickly"

# A plotfile whose header claims a 512x512x384 box over a 700-byte FAB file: refused before
# anything of the claimed size (1.5 GB of float64) is allocated.
/usr/bin/python3 "$TESTS/golden/make_plotfile.py" claim.plt >/dev/null
sed -i 's/((0,0,0) (31,31,15) (0,0,0)) ((0,0,0) (63,63,31) (0,0,0))/((0,0,0) (511,511,383) (0,0,0)) ((0,0,0) (1023,1023,767) (0,0,0))/' claim.plt/Header
sed -i 's/((0,0,0) (15,15,15) (0,0,0))/((0,0,0) (511,511,383) (0,0,0))/' claim.plt/Level_0/Cell_H
truncate -s 700 claim.plt/Level_0/Cell_D_00000
peak_kib=$(/usr/bin/python3 - "$VS" "$WORK" <<'PY2'
import resource, subprocess, sys
vs, work = sys.argv[1], sys.argv[2]
r = subprocess.run([vs, "convert", work + "/claim.plt", "-o", work + "/claim", "-q"], capture_output=True, text=True)
lines = r.stderr.strip().splitlines()
assert r.returncode == 2 and len(lines) == 1 and lines[0].startswith("volstream: "), (r.returncode, r.stderr)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
PY2
) || fail "claimed plotfile box: not one line with exit status 2"
[ "$peak_kib" -lt 400000 ] || fail "claimed plotfile box: peak memory $peak_kib KiB (allocated what the header claims?)"
echo "ok: plotfile claiming a 512x512x384 box refused at $peak_kib KiB peak"
