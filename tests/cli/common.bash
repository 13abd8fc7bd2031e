# Sourced by the CLI tests: $VS is the volstream binary, $WORK a fresh scratch directory.
set -euo pipefail
VS="$1"
WORK="$2"
rm -rf "$WORK" && mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }

# expect_bad_input DESCRIPTION ARGS...: exit status 2 and exactly one line "volstream: ...",
# within a minute (a hang on hostile input is a failure too).
expect_bad_input() {
  local what="$1"; shift
  local status=0
  timeout 60 "$VS" "$@" >"$WORK/out.txt" 2>"$WORK/err.txt" || status=$?
  [ "$status" = 2 ] || fail "$what: exit status $status, expected 2 (stderr: $(head -c 300 "$WORK/err.txt"))"
  [ "$(wc -l <"$WORK/err.txt")" = 1 ] || fail "$what: expected one line on stderr, got: $(cat "$WORK/err.txt")"
  grep -q '^volstream: ' "$WORK/err.txt" || fail "$what: message does not start with 'volstream: '"
  echo "ok: $what -> $(cat "$WORK/err.txt")"
}

# random_points DATASET N SEED: N random world points in the dataset's domain (slightly beyond).
random_points() {
  "$VS" info "$1" --json | awk -v n="$2" -v seed="$3" '
    /"lower": \[/ { mode = "lo"; k = 0; next }
    /"upper": \[/ { mode = "hi"; k = 0; next }
    mode != "" && /^[ \t]*-?[0-9]/ { v = $1; sub(/,/, "", v); if (mode == "lo") lo[k++] = v; else hi[k++] = v; if (k == 3) mode = ""; next }
    END {
      srand(seed);
      for (i = 0; i < n; i++) {
        line = "";
        for (a = 0; a < 3; a++) { e = 0.02 * (hi[a] - lo[a]); line = line sprintf("%.9g ", lo[a] - e + rand() * (hi[a] - lo[a] + 2 * e)); }
        print line;
      }
    }'
}

# compare_probes A B [N]: same count, NaN exactly where the other is NaN (but for N points), and |a - b| <= 1e-5 |b|
# plus 1e-6 of the largest magnitude: a float sum of weighted cell values rounds relative to
# its terms, not its result (g++ 13 missed 1e-5 |b| + 1e-7 max by 2% at one of 10^4 points, a
# vorticity of 121.5 where the largest is about 1600).
compare_probes() {
  paste "$1" "$2" | awk -v nan_allowed="${3:-0}" '
    function abs(x) { return x < 0 ? -x : x }
    { n++; a[n] = $1; b[n] = $2; if ($2 != "nan" && abs($2) > big) big = abs($2) }
    END {
      for (i = 1; i <= n; i++) {
        if (a[i] == "nan" || b[i] == "nan") { if (a[i] != b[i]) { if (++nan_bad > nan_allowed) { bad++; if (bad < 5) print "nan mismatch line " i ": " a[i] " " b[i] } } else nan++; continue }
        if (abs(a[i] - b[i]) > 1e-5 * abs(b[i]) + 1e-6 * big) { bad++; if (bad < 5) print "line " i ": " a[i] " vs " b[i] }
      }
      print n " points, " nan + 0 " outside, " bad + 0 " mismatches" (nan_bad ? ", " nan_bad + 0 " inside one only (" nan_allowed " allowed)" : ""); exit (bad > 0 || n == 0)
    }'
}
