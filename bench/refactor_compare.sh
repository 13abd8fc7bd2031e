#!/usr/bin/env bash
# Paired before/after timing of two volstream binaries (e.g. the pre-refactor cf4f0f8 build and the
# refactored one) on the same datasets: BASE and NEW alternate, run after run (the order flips each
# round so neither always runs second), on
#   dvr        render JET (ABR DVR, default look)
#   iso        render JET --iso 200,800 --color-field velocity
#   blocks     render JET --integrator blocks --reconstruction trilinear
#   blackbody  render COSMO --optics blackbody
#   play       play JET --steps 0:3 -o frames_%04d.png (PNG sequence)
# all at SIZE (512x512). The main figure is the render time the tool prints ("render WxH: X s";
# for play the "render" stage total of its stage table); the whole command's wall time is given too.
# Prints median/min/max per command per binary, the NEW/BASE ratio of the medians, and the spread
# (min..max) of the per-round NEW/BASE ratios: run BASE against itself to see the noise level.
# The datasets (JET: demo jet, JET_CELLS cells, 3 steps; COSMO: demo cosmo, COSMO_CELLS cells) are
# written once by BASE into SCRATCH and reused. Every run's output stays in SCRATCH/logs.
#
# usage: bench/refactor_compare.sh BASE_BINARY NEW_BINARY SCRATCH_DIR [N=5]
#        SIZE=512x512 JET_CELLS=2e6 COSMO_CELLS=1e6 WARMUP=1 (untimed rounds first) DEVICE=cpu
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
BASE="$(realpath "$1")"
NEW="$(realpath "$2")"
SCRATCH="$3"
N="${4:-5}"
SIZE="${SIZE:-512x512}"
JET_CELLS="${JET_CELLS:-2e6}"
COSMO_CELLS="${COSMO_CELLS:-1e6}"
WARMUP="${WARMUP:-1}"
DEVICE="${DEVICE:-cpu}"
mkdir -p "$SCRATCH/logs"
SCRATCH="$(realpath "$SCRATCH")"
JET="$SCRATCH/jet_$JET_CELLS"
COSMO="$SCRATCH/cosmo_$COSMO_CELLS"
RESULTS="$SCRATCH/results.tsv"

[ -f "$JET/manifest.json" ] || "$BASE" demo jet --cells "$JET_CELLS" --steps 3 -o "$JET" -q >/dev/null
[ -f "$COSMO/manifest.json" ] || "$BASE" demo cosmo --cells "$COSMO_CELLS" --steps 1 -o "$COSMO" -q >/dev/null

COMMANDS=(dvr iso blocks blackbody play)
# args NAME BIN_LABEL: the volstream arguments of a command (outputs go to SCRATCH/out_LABEL).
args() {
  local out="$SCRATCH/out_$2"
  mkdir -p "$out"
  case "$1" in
    dvr) echo "render $JET --size $SIZE --device $DEVICE -o $out/dvr.png" ;;
    iso) echo "render $JET --iso 200,800 --color-field velocity --size $SIZE --device $DEVICE -o $out/iso.png" ;;
    blocks) echo "render $JET --integrator blocks --reconstruction trilinear --size $SIZE --device $DEVICE -o $out/blocks.png" ;;
    blackbody) echo "render $COSMO --optics blackbody --size $SIZE --device $DEVICE -o $out/blackbody.png" ;;
    play) echo "play $JET --steps 0:3 --size $SIZE --device $DEVICE -o $out/frames_%04d.png -q" ;;
  esac
}

# run CMD LABEL BIN ROUND: one timed run, appended to RESULTS as "cmd label round render_s wall_s".
run() {
  local cmd="$1" label="$2" bin="$3" round="$4"
  local log="$SCRATCH/logs/${cmd}_${label}_${round}.log"
  local t0 t1 render
  t0=$(date +%s%N)
  # shellcheck disable=SC2046
  "$bin" $(args "$cmd" "$label") >"$log" 2>&1 || { echo "FAILED ($label): $bin $(args "$cmd" "$label")" >&2; cat "$log" >&2; exit 1; }
  t1=$(date +%s%N)
  if [ "$cmd" = play ]; then
    render=$(awk '$1 == "render" && NF == 6 { printf "%.4f", $3 / 1000 }' "$log")
  else
    render=$(sed -nE 's/^render [0-9]+x[0-9]+: ([0-9.eE+-]+) ?s.*/\1/p' "$log" | head -1)
  fi
  [ -n "$render" ] || { echo "no render time in $log" >&2; cat "$log" >&2; exit 1; }
  [ "$round" -gt 0 ] || return 0
  printf "%s\t%s\t%s\t%s\t%.4f\n" "$cmd" "$label" "$round" "$render" "$(echo "($t1 - $t0) / 1000000000" | bc -l)" >>"$RESULTS"
}

echo "# $(date -u +%FT%TZ) $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), device $DEVICE, size $SIZE, N=$N (+$WARMUP warm-up)"
echo "# BASE $BASE ($(stat -c %y "$BASE" | cut -d. -f1), sha256 $(sha256sum "$BASE" | cut -c1-12))"
echo "# NEW  $NEW ($(stat -c %y "$NEW" | cut -d. -f1), sha256 $(sha256sum "$NEW" | cut -c1-12))"
echo "# JET  $JET ($("$BASE" info "$JET" | awk '$1 == "cells" { print $2; exit }') cells), COSMO $COSMO ($("$BASE" info "$COSMO" | awk '$1 == "cells" { print $2; exit }') cells)"
: >"$RESULTS"
for ((round = 1 - WARMUP; round <= N; ++round)); do
  for cmd in "${COMMANDS[@]}"; do
    if (( (round + 1000) % 2 )); then
      run "$cmd" BASE "$BASE" "$round"; run "$cmd" NEW "$NEW" "$round"
    else
      run "$cmd" NEW "$NEW" "$round"; run "$cmd" BASE "$BASE" "$round"
    fi
  done
done

# Table: per command and measure, median/min/max of BASE and NEW, NEW/BASE of the medians, and the
# min..max of the per-round ratios.
awk -F'\t' -v order="${COMMANDS[*]}" '
  function median(a, n,   i, j, t, b) {
    for (i = 1; i <= n; i++) b[i] = a[i];
    for (i = 2; i <= n; i++) for (j = i; j > 1 && b[j-1] > b[j]; j--) { t = b[j]; b[j] = b[j-1]; b[j-1] = t }
    return n % 2 ? b[(n+1)/2] : (b[n/2] + b[n/2+1]) / 2
  }
  function stats(key, a, n,   i) { n = cnt[key]; for (i = 1; i <= n; i++) a[i] = v[key, i]; return n }
  {
    for (m = 1; m <= 2; m++) {
      key = $1 SUBSEP m SUBSEP $2
      v[key, ++cnt[key]] = $(3 + m)
      r[$1, m, $2, $3] = $(3 + m)
    }
    rounds[$3] = 1
  }
  END {
    printf "%-10s %-7s %28s %28s %9s %15s\n", "command", "measure", "BASE median [min, max] s", "NEW median [min, max] s", "NEW/BASE", "per-round range"
    nc = split(order, cmds, " ")
    for (c = 1; c <= nc; c++) for (m = 1; m <= 2; m++) {
      cmd = cmds[c]
      kb = cmd SUBSEP m SUBSEP "BASE"; kn = cmd SUBSEP m SUBSEP "NEW"
      nb = stats(kb, ab); nn = stats(kn, an)
      if (nb == 0 || nn == 0) continue
      lo = hi = ""; mb = median(ab, nb); mn = median(an, nn)
      minb = maxb = ab[1]; for (i = 2; i <= nb; i++) { if (ab[i] < minb) minb = ab[i]; if (ab[i] > maxb) maxb = ab[i] }
      minn = maxn = an[1]; for (i = 2; i <= nn; i++) { if (an[i] < minn) minn = an[i]; if (an[i] > maxn) maxn = an[i] }
      for (k in rounds) {
        kb = cmd SUBSEP m SUBSEP "BASE" SUBSEP k; kn = cmd SUBSEP m SUBSEP "NEW" SUBSEP k
        if (!(kb in r) || !(kn in r) || r[kb] <= 0) continue
        q = r[kn] / r[kb]
        if (lo == "" || q < lo) lo = q
        if (hi == "" || q > hi) hi = q
      }
      printf "%-10s %-7s %10.3f [%6.3f, %6.3f] %10.3f [%6.3f, %6.3f] %9.3f %7.3f..%-7.3f\n", cmd, (m == 1 ? "render" : "wall"),
        mb, minb, maxb, mn, minn, maxn, (mb > 0 ? mn / mb : 0), lo, hi
    }
  }' "$RESULTS"
echo "# raw runs: $RESULTS (command, binary, round, render_s, wall_s); outputs in $SCRATCH/logs"
