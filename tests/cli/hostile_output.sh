#!/usr/bin/env bash
# Class 5, atomic and checked output. A full disk is simulated with a file-size limit (ulimit
# -f; writes past it fail with EFBIG, SIGXFSZ ignored), ffmpeg failures with fake ffmpegs on
# PATH. Every failure is one line and exit 2, and leaves nothing at the final path and no
# temporary behind; a convert that fails into an existing dataset leaves it as it was.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 2 -o ds -q >/dev/null
mkdir out
# full CMD...: runs volstream with at most 1 KiB per written file.
full() { (trap '' XFSZ; ulimit -f 1; exec "$VS" "$@"); }
expect_full() {
  local what="$1"; shift
  local status=0
  full "$@" >out.txt 2>err.txt || status=$?
  [ "$status" = 2 ] && [ "$(wc -l <err.txt)" = 1 ] || fail "$what on a full disk: status $status, $(cat err.txt)"
  [ -z "$(ls -A out)" ] || fail "$what left files: $(ls -A out)"
  echo "ok: $what on a full disk -> $(cat err.txt)"
}
expect_full "render PNG" render ds -o out/x.png --size 64x64
expect_full "render PFM" render ds -o out/x.pfm --size 64x64
expect_full "play PNG sequence" play ds --size 64x64 -q -o "out/f_%d.png"
expect_full "play timeline" play ds --size 8x8 -q --timeline out/t.json
"$VS" play ds --size 8x8 -q --timeline t.json >/dev/null
expect_full "timeline SVG" timeline t.json -o out/t.svg
/usr/bin/python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<8000f', *range(8000)))" >grid.raw
expect_full "convert" convert grid.raw --dims 20,20,20 -o out/c -q

# ffmpeg that exits 0 without writing a video, and one that fails.
mkdir bin0 bin1
printf '#!/bin/sh\ncat >/dev/null\nexit 0\n' >bin0/ffmpeg
printf '#!/bin/sh\ncat >/dev/null\necho "encoder broke" >&2\nexit 1\n' >bin1/ffmpeg
chmod +x bin0/ffmpeg bin1/ffmpeg
PATH="$WORK/bin0:$PATH" expect_bad_input "ffmpeg writes nothing" play ds --size 8x8 -q -o out/v.mp4
PATH="$WORK/bin1:$PATH" expect_bad_input "ffmpeg fails" play ds --size 8x8 -q -o out/v.mp4
grep -q "encoder broke" err.txt || fail "ffmpeg's message not passed on: $(cat err.txt)"
[ -z "$(ls -A out)" ] || fail "a failed play left files: $(ls -A out)"

# A convert that fails part way into an existing dataset changes nothing.
/usr/bin/python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<8f', *range(8)))" >a.raw
/usr/bin/python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<8f', 1,2,3,4,5,6,7,float('inf')))" >b.raw
"$VS" convert a.raw --dims 2,2,2 -o old -q >/dev/null
cp -r old old.copy
expect_bad_input "convert failing into an existing dataset" convert a.raw b.raw --dims 2,2,2 -o old -q
diff -r old old.copy >/dev/null || fail "a failed convert changed the existing dataset"
[ "$(ls -A . | grep -c part)" = 0 ] || fail "temporary left: $(ls -A)"
"$VS" convert b.raw a.raw --dims 2,2,2 --series -o old -q >/dev/null 2>&1 && fail "inf accepted"
"$VS" convert a.raw a.raw --dims 2,2,2 --series -o old -q >/dev/null || fail "convert over an old dataset failed"
"$VS" info old --json | grep -q '"steps": 2' || fail "old dataset not replaced"
mkdir other && touch other/precious
expect_bad_input "convert into a foreign directory" convert a.raw --dims 2,2,2 -o other
[ -f other/precious ] || fail "convert wrote into a foreign directory"
echo "ok: outputs are atomic"
