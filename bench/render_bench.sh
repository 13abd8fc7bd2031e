#!/usr/bin/env bash
# Renderer benchmark: the jet demo (default look: vorticity, log scale) at each cell count,
# 512x512 and 1024x1024, with and without empty-space skipping and adaptive sampling.
# Prints frame (render) time, its CPU time over all threads, samples and samples/s; the raw
# output of every run goes to OUT_DIR.
# usage: bench/render_bench.sh VOLSTREAM_BINARY OUT_DIR [CELLS...] (default: 1e6)
#        DEVICE=cpu|cuda|auto (default auto), SIZES="512 1024" override the defaults.
set -euo pipefail
VS="$(realpath "$1")"
OUT="$2"
shift 2
CELLS=("${@:-1e6}")
SIZES=(${SIZES:-512 1024})
DEVICE="${DEVICE:-auto}"
mkdir -p "$OUT"
echo "# $(date -u +%FT%TZ) $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), device $DEVICE"
printf "%-6s %-9s %-22s %15s %9s %8s %9s %10s\n" cells size mode visible render_s cpu_s Msamples Msamples/s
for n in "${CELLS[@]}"; do
  dir="$OUT/jet_$n"
  [ -f "$dir/manifest.json" ] || "$VS" demo jet --cells "$n" --steps 1 -o "$dir" -q >/dev/null
  for size in "${SIZES[@]}"; do
    for mode in "default" "--no-skip" "--no-adaptive" "--no-skip --no-adaptive"; do
      flags=""
      [ "$mode" = default ] || flags="$mode"
      log="$OUT/render_${n}_${size}_$(echo "$mode" | tr -d ' -').log"
      # shellcheck disable=SC2086
      "$VS" render "$dir" --size "${size}x${size}" --device "$DEVICE" $flags -o "$OUT/jet_${n}_${size}.png" >"$log"
      visible=$(sed -nE 's/.*, ([0-9]+) of ([0-9]+) ABRs visible.*/\1\/\2/p' "$log")
      read -r secs cpu ms mps < <(sed -nE 's/^render [0-9x]+: ([0-9.]+)s \(([0-9.]+)s CPU time\), ([0-9.]+) M samples, ([0-9.]+) M samples\/s.*/\1 \2 \3 \4/p' "$log")
      printf "%-6s %-9s %-22s %15s %9s %8s %9s %10s\n" "$n" "${size}x${size}" "$mode" "$visible" "$secs" "$cpu" "$ms" "$mps"
    done
  done
done
