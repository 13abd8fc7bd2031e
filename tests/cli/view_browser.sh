#!/usr/bin/env bash
# view end to end in a real browser: headless chromium (driven by selenium through chromedriver,
# tests/cli/view_browser.py) loads the page, gets frames, orbits, moves the time slider, edits the
# transfer function, reloads the URL's state, plays (through the streaming pipeline) and pauses,
# opens a second tab, sends garbage over the socket, loads the page of a server on [::1] (when
# there is one); then Ctrl-C stops the server cleanly. Skipped (77) without the viewer or the browser.
HERE="$(cd "$(dirname "$0")" && pwd)"
source "$HERE/common.bash"
cd "$WORK"
if ! "$VS" view --help >/dev/null 2>&1; then echo "skip: volstream built without the viewer"; exit 77; fi

"$VS" demo jet --cells 20000 --steps 3 -o ds -q >/dev/null
expect_bad_input "view: port out of range" view ds --port 70000
expect_bad_input "view: bad host" view ds --host "1.2.3.4,5"
expect_bad_input "view: bad IPv6 host" view ds --host "::1::2"
expect_bad_input "view: port in --host" view ds --host "[::1]:8080"
expect_bad_input "view: missing dataset" view nosuch
expect_bad_input "view: bad render option" view ds --tf nosuchmap

# --host ::1: an IPv6 socket and a [::1] URL, when the machine has an IPv6 loopback and civetweb
# was built with IPv6 (Debian's is not: then a one-line error, exit status 2).
URL6=""
if ! grep -q '^00000000000000000000000000000001 ' /proc/net/if_inet6 2>/dev/null; then
  echo "skip: view --host ::1: no IPv6 loopback (/proc/net/if_inet6)"
else
  "$VS" view ds --host ::1 --port 0 >server6.log 2>err6.txt &
  SERVER6=$!
  for _ in $(seq 100); do { grep -q 'http://' server6.log || ! kill -0 $SERVER6; } 2>/dev/null && break; sleep 0.1; done
  if URL6=$(grep -o 'http://\[::1\]:[0-9]*/' server6.log); then
    trap 'kill $SERVER6 2>/dev/null || true' EXIT
    /usr/bin/python3 -c 'import sys, urllib.request; sys.exit("volstream view" not in urllib.request.urlopen(sys.argv[1], timeout=10).read().decode())' "$URL6" ||
      fail "no page from $URL6"
    echo "ok: the page over IPv6 at $URL6"
  else
    status=0
    wait $SERVER6 || status=$?
    [ "$status" = 2 ] && grep -q "no IPv6 support" err6.txt || fail "view --host ::1 (status $status): $(cat server6.log err6.txt)"
    echo "skip: serving over IPv6: $(cat err6.txt)"
    URL6="" SERVER6=""
  fi
fi

if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null || ! /usr/bin/python3 -c 'import selenium' 2>/dev/null; then
  echo "skip: chromium, chromedriver or python3-selenium missing (scripts/setup.sh installs them)"
  exit 77
fi

"$VS" view ds --port 0 >server.log 2>&1 &
SERVER=$!
trap 'kill $SERVER ${SERVER6:-} 2>/dev/null || true' EXIT
for _ in $(seq 100); do grep -q 'http://' server.log && break; sleep 0.1; done
URL=$(grep -o 'http://[0-9.:]*/' server.log) || fail "no URL printed: $(cat server.log)"
echo "server at $URL"

timeout 120 /usr/bin/python3 "$HERE/view_browser.py" "$URL" $URL6 || fail "browser test failed (server log: $(cat server.log))"
if [ -n "$URL6" ]; then kill -INT $SERVER6; wait $SERVER6 || fail "IPv6 server exit status $? after SIGINT"; fi
kill -0 $SERVER || fail "server died: $(cat server.log)"

# What the viewer adds to a small frame's render (message, JPEG, socket, decode) is a few ms; 40
# ms or more means a frame waits on TCP (Nagle's algorithm against the client's delayed ACK).
PORT=${URL##*:}
PORT=${PORT%/}
/usr/bin/python3 "$HERE/../../bench/view_latency.py" --port "$PORT" --size 64x48 --frames 15 >latency.txt ||
  fail "latency client failed: $(cat latency.txt)"
overhead=$(awk '/^latency/ {l = $(NF - 5)} /^render/ {r = $(NF - 5)} END {print l - r}' latency.txt)
awk -v o="$overhead" 'BEGIN {exit !(o < 35)}' || fail "viewer adds $overhead ms to a 64x48 frame: $(cat latency.txt)"
echo "ok: the viewer adds $overhead ms (median) to a 64x48 frame's render"

kill -INT $SERVER
status=0
timeout 20 tail --pid=$SERVER -f /dev/null || fail "server did not stop on SIGINT"
wait $SERVER || status=$?
trap - EXIT
[ "$status" = 0 ] || fail "server exit status $status after SIGINT"
grep -q "stopped" server.log || fail "no clean stop: $(cat server.log)"
echo "ok: stopped cleanly on Ctrl-C"
