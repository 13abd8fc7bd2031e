#!/usr/bin/env bash
# CPU renderer speed (issue 14), a baseline binary and a new one paired in one run, alternated:
#   layered: a 3-level AMReX plotfile of 720,896 cells written by bench/make_amr_plotfile.py,
#            512x512, six narrow Gaussian layers on log density (bench/layers_opacity.py, as yt's
#            ColorTransferFunction.add_layers(6)): transparent, so no ray stops early;
#   jet:     `demo jet --cells 1e6`, 512x512, the demo's default look.
# For each case and binary: the whole command's wall time (median, min, max over REPEATS runs)
# and the render stage's samples per second as `render` prints them. The new binary runs twice:
# as it chooses (AVX2 where the CPU has it) and as on a CPU without AVX2
# (VOLSTREAM_CPU_BASELINE=1, tag new-sse2). With YT=1 also yt's volume
# renderer on the same plotfile (installs python3-yt with apt-get when it is missing); yt's
# second render is the fair figure.
# usage: bench/cpu_speed.sh BASE_BINARY NEW_BINARY OUT_DIR   (REPEATS=7, YT=0|1)
set -euo pipefail
BASE="$(realpath "$1")"
NEW="$(realpath "$2")"
OUT="$3"
REPEATS="${REPEATS:-7}"
HERE="$(cd "$(dirname "$0")" && pwd)"
PY=/usr/bin/python3
mkdir -p "$OUT"
LO=6e-4
HI=4

echo "# $(date -u +%FT%TZ) $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "# load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# base $BASE"
echo "# new  $NEW"

[ -f "$OUT/amr.plt/Header" ] || "$PY" "$HERE/make_amr_plotfile.py" "$OUT/amr.plt"
# Datasets in the new binary's format (the base reads it and ignores what it does not know, such
# as the stored ABR BVH, which it builds at load as it always did).
[ -f "$OUT/amr/manifest.json" ] || "$NEW" convert "$OUT/amr.plt" -o "$OUT/amr" -q >/dev/null
[ -f "$OUT/jet/manifest.json" ] || "$NEW" demo jet --cells 1e6 --steps 1 -o "$OUT/jet" -q >/dev/null
OPACITY="$("$PY" "$HERE/layers_opacity.py" "$LO" "$HI" 6 0.3)"

declare -A ARGS
ARGS[layered]="$OUT/amr --log --range $LO,$HI --opacity $OPACITY --size 512x512"
ARGS[jet]="$OUT/jet --size 512x512"

# One run: prints "wall_s render_s Msamples Msamples_per_s".
run_once() {
  local bin="$1" case="$2" tag="$3" log start end baseline=0
  [ "$tag" = new-sse2 ] && baseline=1
  log="$OUT/${case}_${tag}.log"
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  VOLSTREAM_CPU_BASELINE=$baseline "$bin" render ${ARGS[$case]} -o "$OUT/${case}_${tag}.pfm" >"$log"
  end=$(date +%s.%N)
  read -r secs ms mps < <(sed -nE 's/^render [0-9x]+: ([0-9.]+)s \([0-9.]+s CPU time\), ([0-9.]+) M samples, ([0-9.]+) M samples\/s.*/\1 \2 \3/p' "$log")
  echo "$(echo "$end - $start" | bc -l) $secs $ms $mps"
}

# median, min and max of the numbers on stdin
stats() { sort -g | awk '{v[NR]=$1} END {m = NR % 2 ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2; printf "%.3f [%.3f, %.3f]", m, v[1], v[NR]}'; }

for case in layered jet; do
  : >"$OUT/${case}_runs.txt"
  for ((i = 0; i < REPEATS; ++i)); do  # alternate, so that load changes hit both alike
    echo "base $(run_once "$BASE" "$case" base)" >>"$OUT/${case}_runs.txt"
    echo "new $(run_once "$NEW" "$case" new)" >>"$OUT/${case}_runs.txt"
    echo "new-sse2 $(run_once "$NEW" "$case" new-sse2)" >>"$OUT/${case}_runs.txt"
  done
  for tag in base new new-sse2; do
    wall=$(awk -v t=$tag '$1 == t {print $2}' "$OUT/${case}_runs.txt" | stats)
    mps=$(awk -v t=$tag '$1 == t {print $5}' "$OUT/${case}_runs.txt" | stats)
    ms=$(awk -v t=$tag '$1 == t {print $4; exit}' "$OUT/${case}_runs.txt")
    printf "%-8s %-8s whole command %s s, render %s M samples/s, %s M samples\n" "$case" "$tag" "$wall" "$mps" "$ms"
  done
  "$PY" - "$OUT/${case}_base.pfm" "$OUT/${case}_new.pfm" <<'EOF'
import sys
import numpy as np
def pfm(path):
    with open(path, "rb") as f:
        f.readline(); w, h = map(int, f.readline().split()); scale = float(f.readline())
        return np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, -1)
a, b = pfm(sys.argv[1]), pfm(sys.argv[2])
def srgb8(x):
    x = np.clip(x, 0, 1)
    return np.round(255 * np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055))
d = srgb8(a) - srgb8(b)
print("         images: RMSE %.4f 8-bit codes, max %d codes, max linear diff %.2e" %
      (np.sqrt(np.mean(d * d)), np.abs(d).max(), np.abs(a - b).max()))
EOF
  if cmp -s "$OUT/${case}_new.pfm" "$OUT/${case}_new-sse2.pfm"; then
    echo "         new and new-sse2 images: identical"
  else
    echo "         new and new-sse2 images: DIFFER"
  fi
done
echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"

if [ "${YT:-0}" = 1 ]; then
  "$PY" -c 'import yt' 2>/dev/null || apt-get install -y python3-yt >"$OUT/apt_yt.log" 2>&1
  for ((i = 0; i < 3; ++i)); do
    "$PY" "$HERE/yt_render.py" "$OUT/amr.plt" "$LO" "$HI" 512 "$OUT/layered_yt.png" 6 | tee -a "$OUT/yt_runs.txt"
  done
fi
