#!/usr/bin/env bash
# Class 6, temporary files: render --demo uses a fresh mkdtemp directory (a link planted at the
# old predictable path is never followed) and removes it, also on Ctrl-C (SIGINT) and SIGTERM.
source "$(dirname "$0")/common.bash"
cd "$WORK"
mkdir tmp victim && echo keep >victim/manifest.json
export TMPDIR="$WORK/tmp"
for name in jet cosmo; do ln -s "$WORK/victim" "tmp/volstream_render_${name}_$$"; done
"$VS" render --demo jet --cells 10000 --size 16x16 -o x.png >/dev/null || fail "render --demo failed"
[ "$(cat victim/manifest.json)" = keep ] || fail "render --demo wrote through a planted link"
[ "$(ls tmp | grep -vc '^volstream_render_.*_'$$'$')" = 0 ] || fail "temporary left: $(ls tmp)"
rm tmp/*
for sig in INT TERM; do
  # A background job starts with SIGINT ignored; exec volstream with it restored, as from a terminal.
  /usr/bin/python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.execv(sys.argv[1], sys.argv[1:])' \
    "$VS" render --demo jet --cells 3e6 --size 16x16 -o y.png >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 100); do [ -n "$(ls -A tmp)" ] && break; sleep 0.1; done
  [ -n "$(ls -A tmp)" ] || fail "no temporary directory appeared"
  sleep 0.3
  kill -s "$sig" "$pid"
  wait "$pid" || true
  [ -z "$(ls -A tmp)" ] || fail "SIG$sig left $(ls -A tmp)"
  echo "ok: SIG$sig removes the demo's temporary directory"
done
