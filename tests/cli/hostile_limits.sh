#!/usr/bin/env bash
# Class 8, limits reachable by mistake: image sizes and the disk a demo or convert needs.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 1 -o ds -q >/dev/null
expect_bad_input "--size above the limit" render ds --size 16384x16384 -o x.png
expect_bad_input "--size above the limit (play)" play ds --size 20000x10 -q
expect_bad_input "bench integrators --size" bench integrators ds --size 100000
expect_bad_input "demo larger than the free disk" demo jet --cells 2e9 --steps 100000 -o big -q
grep -q "GB free" err.txt || fail "no disk estimate in: $(cat err.txt)"
[ ! -e big ] || fail "a refused demo left big"
