#!/usr/bin/env bash
# view end to end in a real browser: headless chromium (driven by selenium through chromedriver,
# tests/cli/view_browser.py) loads the page, gets frames, orbits, moves the time slider, edits the
# transfer function, reloads the URL's state, opens a second tab, sends garbage over the socket;
# then Ctrl-C stops the server cleanly. Skipped (77) without the viewer or the browser.
HERE="$(cd "$(dirname "$0")" && pwd)"
source "$HERE/common.bash"
cd "$WORK"
if ! "$VS" view --help >/dev/null 2>&1; then echo "skip: volstream built without the viewer"; exit 77; fi

"$VS" demo jet --cells 20000 --steps 3 -o ds -q >/dev/null
expect_bad_input "view: port out of range" view ds --port 70000
expect_bad_input "view: bad host" view ds --host "1.2.3.4,5"
expect_bad_input "view: missing dataset" view nosuch
expect_bad_input "view: bad render option" view ds --tf nosuchmap

if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null || ! /usr/bin/python3 -c 'import selenium' 2>/dev/null; then
  echo "skip: chromium, chromedriver or python3-selenium missing (scripts/setup.sh installs them)"
  exit 77
fi

"$VS" view ds --port 0 >server.log 2>&1 &
SERVER=$!
trap 'kill $SERVER 2>/dev/null || true' EXIT
for _ in $(seq 100); do grep -q 'http://' server.log && break; sleep 0.1; done
URL=$(grep -o 'http://[0-9.:]*/' server.log) || fail "no URL printed: $(cat server.log)"
echo "server at $URL"

timeout 120 /usr/bin/python3 "$HERE/view_browser.py" "$URL" || fail "browser test failed (server log: $(cat server.log))"
kill -0 $SERVER || fail "server died: $(cat server.log)"

kill -INT $SERVER
status=0
timeout 20 tail --pid=$SERVER -f /dev/null || fail "server did not stop on SIGINT"
wait $SERVER || status=$?
trap - EXIT
[ "$status" = 0 ] || fail "server exit status $status after SIGINT"
grep -q "stopped" server.log || fail "no clean stop: $(cat server.log)"
echo "ok: stopped cleanly on Ctrl-C"
