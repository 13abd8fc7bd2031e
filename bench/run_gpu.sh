#!/usr/bin/env bash
# GPU benchmarks (scripts/gpu_check.sh runs them): on a GPU machine with local disk,
#   data    the jet demo for streaming (default about 3.1e8 cells, 8 steps) and a 1-step one of
#           1e8 cells for rendering, generated onto local disk (DATA_DIR, never in the repository)
#   stream  `volstream bench stream` over every pipeline level on DEVICE: the table, the timeline
#           (Chrome-trace JSON) and its Gantt charts (SVG, one row per lane and one per stage)
#   render  `volstream render` of the 1e8-cell demo on cuda and on the CPU, RENDER_REPEAT times
#           at each size, summarised as a table
#   mesh    unstructured meshes (issues 12, 13): the tets and mixed demos (MESH_TETS, MESH_MIXED
#           elements) with both encodings, on RENDER_DEVICES at RENDER_SIZES, in the view and
#           looks of bench/umesh_vs_vtk.sh (VTK is not on that machine), as a table
#   view    the browser viewer's latency (issue 16; bench/view_latency.py, a WebSocket client):
#           a 1e6-cell jet at 1280x720 and at the 426x240 preview size while dragging, on
#           RENDER_DEVICES; frames/s while dragging = 1000 / the preview's median latency
# Every command line is echoed and logged with its output, wall time and exit status into LOG_DIR
# (one NAME.log per command, summary.txt for all of them). A part that fails is logged and the
# next part still runs; the exit status is non-zero if any part failed.
#
# usage: bench/run_gpu.sh VOLSTREAM_BINARY LOG_DIR [data|stream|render|mesh|view|all ...]   (default: all)
# Environment (defaults for the GPU machine; tiny values smoke-test it on a CPU):
#   DEVICE=cuda         device of the stream benchmark; render compares RENDER_DEVICES
#   CELLS=3.1e8 STEPS=8 the streamed demo (the demo's cell count is approximate, a few %: 3.1e8
#                       gives at least MIN_CELLS=3e8, which is checked when CELLS is not set)
#   RENDER_CELLS=1e8    the rendered demo (default: 1e8, or CELLS when that is smaller)
#   RENDER_DEVICES="cuda cpu" (default: "cuda cpu" when DEVICE=cuda, else DEVICE)
#   RENDER_SIZES="512 1024" RENDER_REPEAT=2 (also the mesh part's)
#   MESH_TETS=1e6 MESH_MIXED=5e5 (mesh demo elements)   VIEW_FRAMES=40 (frames per latency run)
#   STREAM_SIZE=1024x1024 (cuda) / 256x256 (otherwise); STREAM_STEPS (bench --steps, default all)
#   LEVELS=a,b,...      only these levels (default all, in one run). Each LEVELS run writes its own
#                       stream_<levels>.* files; the runs found in LOG_DIR are merged into
#                       stream_all_timeline.{json,svg} and stream_all_table.txt, so the levels can
#                       be spread over several commands when one run would exceed a time limit.
#   STREAM_ARGS="..."   more bench stream options (e.g. --field vorticity --log --tf inferno)
#   DATA_DIR=${TMPDIR:-/tmp}/volstream_bench   datasets are kept there for the next part/run
#                       (REGEN=1 regenerates them, CLEAN_DATA=1 removes them at the end)
#   CMD_TIMEOUT=SECONDS kill (and log as timed out) any single command running longer
#   DEMO_ARGS="..."     `volstream demo` options (default --fields vorticity; add --file-order for
#                       real flattening in the levels before preordered, twice the values on
#                       disk); DEMO_FIELDS=1 is the number of fields written, for the space check
# Disk: one field with per-ABR ranges is about 32 GB at 3.1e8 cells x 8 steps (all 3 fields of the
# jet demo would need about 69 GB, more than the GPU machine's 64 GiB disk); the space is checked
# before each demo is generated (a part fails at once when it cannot fit).
set -euo pipefail

usage() { echo "usage: bench/run_gpu.sh VOLSTREAM_BINARY LOG_DIR [data|stream|render|mesh|view|all ...]" >&2; exit 2; }
[ $# -ge 2 ] || usage
VS="$(realpath "$1")"
[ -x "$VS" ] || { echo "run_gpu.sh: no volstream binary at $1" >&2; exit 2; }
LOG_DIR="$(realpath -m "$2")"
shift 2
PARTS=("${@:-all}")
for p in "${PARTS[@]}"; do
  case $p in data | stream | render | mesh | view | all) ;; *) echo "run_gpu.sh: unknown part '$p'" >&2; usage ;; esac
done
[[ " ${PARTS[*]} " == *" all "* ]] && PARTS=(data stream render mesh view)

REPO="$(realpath "$(dirname "$0")/..")"
DEVICE="${DEVICE:-cuda}"
MIN_CELLS="${MIN_CELLS:-$([ -z "${CELLS:-}" ] && echo 3e8 || echo 0)}"
CELLS="${CELLS:-3.1e8}"
STEPS="${STEPS:-8}"
RENDER_CELLS="${RENDER_CELLS:-$(awk -v c="$CELLS" 'BEGIN { print (c + 0 < 1e8) ? c : "1e8" }')}"
if [ "$DEVICE" = cuda ]; then RENDER_DEVICES="${RENDER_DEVICES:-cuda cpu}"; else RENDER_DEVICES="${RENDER_DEVICES:-$DEVICE}"; fi
RENDER_SIZES="${RENDER_SIZES:-512 1024}"
RENDER_REPEAT="${RENDER_REPEAT:-2}"
if [ "$DEVICE" = cuda ]; then STREAM_SIZE="${STREAM_SIZE:-1024x1024}"; else STREAM_SIZE="${STREAM_SIZE:-256x256}"; fi
STREAM_STEPS="${STREAM_STEPS:-}"
MESH_TETS="${MESH_TETS:-1e6}"
MESH_MIXED="${MESH_MIXED:-5e5}"
VIEW_FRAMES="${VIEW_FRAMES:-40}"
LEVELS="${LEVELS:-}"
STREAM_ARGS="${STREAM_ARGS:-}"
DATA_DIR="$(realpath -m "${DATA_DIR:-${TMPDIR:-/tmp}/volstream_bench}")"
CMD_TIMEOUT="${CMD_TIMEOUT:-}"
DEMO_ARGS="${DEMO_ARGS:---fields vorticity}"
DEMO_FIELDS="${DEMO_FIELDS:-1}"
case "$DATA_DIR/" in "$REPO"/*) echo "run_gpu.sh: DATA_DIR $DATA_DIR is inside the repository; use local disk (/tmp)" >&2; exit 2 ;; esac

mkdir -p "$LOG_DIR" "$DATA_DIR"
SUMMARY="$LOG_DIR/summary.txt"
STREAM_DS="$DATA_DIR/jet_${CELLS}_${STEPS}"
RENDER_DS="$DATA_DIR/jet_${RENDER_CELLS}_1"

note() { echo "$*" | tee -a "$SUMMARY"; }

# run NAME COMMAND...: echoes the command line, runs it with stdout and stderr into
# LOG_DIR/NAME.log (and this script's stdout), then logs its wall time and exit status.
run() {
  local name="$1"
  shift
  local log="$LOG_DIR/$name.log" cmd status=0 t0 t1
  cmd="$(printf '%q ' "$@")"
  note "\$ ${cmd% }"
  echo "\$ ${cmd% }" >"$log"
  t0=$(date +%s.%N)
  local limit=()
  if [ -n "$CMD_TIMEOUT" ]; then limit=(timeout --kill-after=10 "$CMD_TIMEOUT"); fi
  # (In "{ ...; } || true" a failure does not stop the script; PIPESTATUS has the command's.)
  { "${limit[@]}" "$@" 2>&1 | tee -a "$log"; status=${PIPESTATUS[0]}; } || true
  t1=$(date +%s.%N)
  local secs
  secs=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
  if [ "$status" = 0 ]; then
    note "  -> ok, ${secs} s ($name.log)"
  elif [ "$status" = 124 ] || [ "$status" = 137 ]; then
    note "  -> TIMED OUT after ${secs} s (CMD_TIMEOUT=$CMD_TIMEOUT; $name.log)"
  else
    note "  -> FAILED with exit status $status after ${secs} s ($name.log)"
  fi
  return "$status"
}

# Disk bytes of a jet demo (measured at 1e6 and 1e7 cells, bench/RESULTS.md): topology about
# 40 B per cell; per field and step 4 B per cell of values and 8 B per ABR of ranges (0.4 ABRs
# per cell); DEMO_FIELDS (1) fields; --file-order in DEMO_ARGS adds a copy of the values and a
# 4 B index per cell; 5% slack.
demo_bytes() {
  local order=0
  [[ " $DEMO_ARGS " == *" --file-order "* ]] && order=1
  awk -v c="$1" -v s="$2" -v f="$DEMO_FIELDS" -v o="$order" \
    'BEGIN { printf "%.0f", c * (40 + 4 * o + s * f * (4 + 3.2 + 4 * o)) * 1.05 }'
}
free_bytes() { df --output=avail -B1 "$DATA_DIR" | tail -1 | tr -d ' '; }

# The streamed and rendered demos are kept in DATA_DIR; a directory without the marker written
# after a complete run is regenerated, and so is every one with REGEN=1.
ensure_demo() {
  local dir="$1" cells="$2" steps="$3" name
  name="demo_$(basename "$dir")"
  if [ -f "$dir/.run_gpu_complete" ] && [ "${REGEN:-0}" != 1 ]; then
    note "# $dir: reused ($(cat "$dir/.run_gpu_complete"))"
    return 0
  fi
  rm -rf "$dir"
  local need avail
  need=$(demo_bytes "$cells" "$steps")
  avail=$(free_bytes)
  note "# $dir: needs about $((need / 1000000000)) GB, $((avail / 1000000000)) GB free on $(df --output=target "$DATA_DIR" | tail -1)"
  if [ "$need" -gt "$avail" ]; then
    note "not enough disk space for $dir (DATA_DIR elsewhere, or smaller CELLS/STEPS)"
    return 1
  fi
  # shellcheck disable=SC2086
  run "$name" "$VS" demo jet --cells "$cells" --steps "$steps" -o "$dir" -q $DEMO_ARGS
  run "info_$(basename "$dir")" "$VS" info "$dir" >/dev/null  # levels, bricks, ABRs, bytes: for the record
  local actual
  actual=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["cell_count"])' "$dir/manifest.json")
  echo "$actual cells, $steps steps, $(date -u +%FT%TZ)" >"$dir/.run_gpu_complete"
  note "# $dir: $actual cells, $steps steps, $(du -sh "$dir" | cut -f1)"
}

part_data() {
  ensure_demo "$STREAM_DS" "$CELLS" "$STEPS"
  local actual
  actual=$(cut -d' ' -f1 "$STREAM_DS/.run_gpu_complete")
  if awk -v a="$actual" -v m="$MIN_CELLS" 'BEGIN { exit !(a + 0 < m + 0) }'; then
    note "WARNING: the streamed demo has $actual cells, fewer than MIN_CELLS=$MIN_CELLS (raise CELLS, REGEN=1)"
  fi
  if [ -f "$RENDER_DS/.run_gpu_complete" ] || [ "$(demo_bytes "$RENDER_CELLS" 1)" -le "$(free_bytes)" ]; then
    ensure_demo "$RENDER_DS" "$RENDER_CELLS" 1
  else
    note "# $RENDER_DS: not enough disk next to $STREAM_DS; the render part makes it (removing the streamed demo)"
  fi
}

# The render part's demo; when the disk cannot hold it next to the streamed one, the streamed one
# goes (the stream part regenerates it when run again).
ensure_render_demo() {
  if [ ! -f "$RENDER_DS/.run_gpu_complete" ] && [ -d "$STREAM_DS" ] &&
    [ "$(demo_bytes "$RENDER_CELLS" 1)" -gt "$(free_bytes)" ]; then
    note "# not enough disk for $RENDER_DS next to $STREAM_DS: removing the streamed demo"
    rm -rf "$STREAM_DS"
  fi
  ensure_demo "$RENDER_DS" "$RENDER_CELLS" 1
}

# Merges every stream_*_timeline.json in LOG_DIR (one process per level; a later run of a level
# replaces an earlier one) and the table rows of their logs, speed-up recomputed over baseline.
merge_stream_runs() {
  python3 - "$LOG_DIR" <<'PY'
import glob, json, os, re, sys
log_dir = sys.argv[1]
runs = sorted((p for p in glob.glob(os.path.join(log_dir, "stream_*_timeline.json")) if not p.endswith("stream_all_timeline.json")),
              key=os.path.getmtime)
if len(runs) < 2:
    sys.exit(0)
by_pid, rows = {}, {}
for path in runs:
    events = json.load(open(path))["traceEvents"]
    for pid in {e["pid"] for e in events}:
        by_pid[pid] = [e for e in events if e["pid"] == pid]
    table = path.replace("_timeline.json", ".log")
    if os.path.exists(table):
        for line in open(table):
            f = line.split()
            if len(f) == 11 and re.match(r"^[0-9.]+$", f[7]) and f[0] in (
                    "baseline", "async-io", "pinned", "direct-io", "preordered", "refit", "overlap"):
                rows[f[0]] = f
merged = [e for pid in sorted(by_pid) for e in by_pid[pid]]
json.dump({"displayTimeUnit": "ms", "traceEvents": merged}, open(os.path.join(log_dir, "stream_all_timeline.json"), "w"))
order = ["baseline", "async-io", "pinned", "direct-io", "preordered", "refit", "overlap"]
base = float(rows["baseline"][7]) if "baseline" in rows else None
with open(os.path.join(log_dir, "stream_all_table.txt"), "w") as out:
    out.write("%-11s %8s %8s %8s %8s %8s %8s %10s %9s %9s %10s\n" % ("level", "read", "upload", "ranges", "refit", "render",
              "output", "frame ms", "frames/s", "speed-up", "read GB/s"))
    for level in order:
        if level in rows:
            f = rows[level]
            speed = "%8.2fx" % (base / float(f[7])) if base else "%9s" % "-"
            out.write("%-11s %s %s %s %s\n" % (f[0], " ".join("%8s" % x for x in f[1:7]), "%10s %9s" % (f[7], f[8]), speed, "%10s" % f[10]))
    out.write("(merged from %d runs: %s; speed-up over the baseline row)\n" % (len(runs), ", ".join(os.path.basename(r) for r in runs)))
print("merged %d runs into stream_all_timeline.json and stream_all_table.txt" % len(runs))
PY
}

part_stream() {
  ensure_demo "$STREAM_DS" "$CELLS" "$STEPS"
  local tag="stream_all-levels" args=()
  if [ -n "$LEVELS" ]; then tag="stream_${LEVELS//,/+}"; args+=(--levels "$LEVELS"); fi
  if [ -n "$STREAM_STEPS" ]; then args+=(--steps "$STREAM_STEPS"); fi
  # shellcheck disable=SC2206
  if [ -n "$STREAM_ARGS" ]; then args+=($STREAM_ARGS); fi
  run "$tag" "$VS" bench stream "$STREAM_DS" --device "$DEVICE" --size "$STREAM_SIZE" "${args[@]}" \
    --timeline "$LOG_DIR/${tag}_timeline.json"
  run "${tag}_gantt" "$VS" timeline "$LOG_DIR/${tag}_timeline.json" -o "$LOG_DIR/${tag}_timeline.svg" \
    --title "bench stream $(basename "$STREAM_DS") on $DEVICE ($STREAM_SIZE)"
  run "${tag}_gantt_stages" "$VS" timeline "$LOG_DIR/${tag}_timeline.json" -o "$LOG_DIR/${tag}_stages.svg" --rows stage \
    --title "bench stream $(basename "$STREAM_DS") on $DEVICE ($STREAM_SIZE), per stage"
  sed -n '/^level /,/^frames identical/p' "$LOG_DIR/$tag.log" >>"$SUMMARY"
  local merged
  merged="$(merge_stream_runs)"
  if [ -n "$merged" ]; then
    note "$merged"
    run stream_all_gantt "$VS" timeline "$LOG_DIR/stream_all_timeline.json" -o "$LOG_DIR/stream_all_timeline.svg" \
      --title "bench stream $(basename "$STREAM_DS") on $DEVICE, merged runs"
  fi
}

part_render() {
  ensure_render_demo
  local table="$LOG_DIR/render_table.txt" dev size rep name failed=0
  printf "%-6s %-10s %-4s %22s %10s %10s %10s %12s\n" device size run visible "render s" "CPU s" "M samples" "M samples/s" >"$table"
  for dev in $RENDER_DEVICES; do
    for size in $RENDER_SIZES; do
      for rep in $(seq "$RENDER_REPEAT"); do
        name="render_${dev}_${size}_$rep"
        run "$name" "$VS" render "$RENDER_DS" --device "$dev" --size "${size}x${size}" -o "$LOG_DIR/render_${dev}_${size}.png" \
          || { failed=1; continue; }
        local visible secs cpu ms mps
        visible=$(sed -nE 's/.*, ([0-9]+) of ([0-9]+) ABRs visible.*/\1\/\2/p' "$LOG_DIR/$name.log")
        read -r secs cpu ms mps < <(sed -nE 's/^render [0-9x]+: ([0-9.]+)s \(([0-9.]+)s CPU time\), ([0-9.]+) M samples, ([0-9.]+) M samples\/s.*/\1 \2 \3 \4/p' "$LOG_DIR/$name.log")
        printf "%-6s %-10s %-4s %22s %10s %10s %10s %12s\n" "$dev" "${size}x${size}" "$rep" "$visible" "$secs" "$cpu" "$ms" "$mps" >>"$table"
      done
    done
  done
  # Best of the runs per device and size, and each device's speed-up over the CPU.
  awk 'NR > 1 && $5 != "" { k = $1 " " $2; if (!(k in best) || $5 < best[k]) best[k] = $5; sizes[$2] = 1; devs[$1] = 1 }
       END { for (s in sizes) for (d in devs) if ((d " " s) in best) {
               line = sprintf("best %-6s %-10s %8.3f s", d, s, best[d " " s]);
               if (d != "cpu" && ("cpu " s) in best) line = line sprintf("  (%.1fx the CPU)", best["cpu " s] / best[d " " s]);
               print line } }' "$table" | sort >>"$table"
  note "# render: $RENDER_DS ($(cut -d' ' -f1 "$RENDER_DS/.run_gpu_complete") cells)"
  tee -a "$SUMMARY" <"$table"
  return "$failed"
}

# A mesh demo of one step, kept in DATA_DIR like the jet demos: one dataset per encoding, stored
# so (a compact mesh built at load from a reference dataset renders on the CPU only, a stored one
# on CUDA too).
ensure_mesh_demo() {
  local kind="$1" elements="$2" enc="$3" dir="$DATA_DIR/${1}_${2}_${3}"
  if [ ! -f "$dir/.run_gpu_complete" ] || [ "${REGEN:-0}" = 1 ]; then
    rm -rf "$dir"
    run "demo_${kind}_${elements}_$enc" "$VS" demo "$kind" --elements "$elements" --steps 1 --encoding "$enc" -o "$dir" -q
    run "info_${kind}_${elements}_$enc" "$VS" info "$dir" >/dev/null
    date -u +%FT%TZ >"$dir/.run_gpu_complete"
  fi
  echo "$dir"
}

# The view and looks of bench/umesh_vs_vtk.sh (haze: every element visible; blobs: empty space to
# skip), so that these rows sit beside its CPU and VTK figures.
MESH_VIEW=(--field density --range 0.02,1.1 --unit-distance 0.01 --camera-pos 2.3,1.6,2.9 --camera-at 0.5,0.5,0.5
  --camera-up 0,1,0 --fov 35 --background 0.06,0.06,0.08)
mesh_opacity() { case "$1" in haze) echo 0.02:0.004,0.15:0.004,0.5:0.03,1.1:0.12 ;; blobs) echo 0.02:0,0.15:0,0.5:0.03,1.1:0.12 ;; esac; }

part_mesh() {
  local table="$LOG_DIR/mesh_table.txt" failed=0 kind elements dir look enc dev size rep name
  printf "%-6s %-8s %-6s %-10s %-6s %-10s %-4s %10s %10s %12s
" mesh elements look encoding device size run "render s"     "M samples" "M samples/s" >"$table"
  for kind in tets mixed; do
    elements=$MESH_TETS
    [ "$kind" = mixed ] && elements=$MESH_MIXED
    for look in haze blobs; do
      for enc in reference compact; do
        dir="$(ensure_mesh_demo "$kind" "$elements" "$enc" | tail -1)"
        for dev in $RENDER_DEVICES; do
          for size in $RENDER_SIZES; do
            for rep in $(seq "$RENDER_REPEAT"); do
              name="mesh_${kind}_${look}_${enc}_${dev}_${size}_$rep"
              run "$name" "$VS" render "$dir" --encoding "$enc" --device "$dev" --size "${size}x${size}" "${MESH_VIEW[@]}"                 --opacity "$(mesh_opacity "$look")" -o "$LOG_DIR/mesh_${kind}_${look}_${enc}_${dev}_${size}.png" ||
                { failed=1; continue; }
              local secs ms mps
              read -r secs ms mps < <(sed -nE 's/^render [0-9x]+: ([0-9.]+)s \([0-9.]+s CPU time\), ([0-9.]+) M samples, ([0-9.]+) M samples\/s.*/\1 \2 \3/p' "$LOG_DIR/$name.log")
              printf "%-6s %-8s %-6s %-10s %-6s %-10s %-4s %10s %10s %12s
" "$kind" "$elements" "$look" "$enc" "$dev"                 "${size}x${size}" "$rep" "$secs" "$ms" "$mps" >>"$table"
            done
          done
        done
      done
    done
  done
  note "# mesh: demos tets $MESH_TETS and mixed $MESH_MIXED elements (each encoding stored)"
  tee -a "$SUMMARY" <"$table"
  return "$failed"
}

# One viewer per device on a 1e6-cell jet; the client sends small orbit steps and waits for each
# frame (bench/view_latency.py), at the full size and at the preview size.
part_view() {
  local ds="$DATA_DIR/jet_1e6_1" dev port=8460 pid failed=0
  [ -f "$ds/.run_gpu_complete" ] || ensure_demo "$ds" 1e6 1
  if ! "$VS" view --help >/dev/null 2>&1; then
    note "view: this volstream was built without the viewer (civetweb, libjpeg-turbo)"
    return 1
  fi
  for dev in $RENDER_DEVICES; do
    port=$((port + 1))
    "$VS" view "$ds" --device "$dev" --port "$port" >"$LOG_DIR/view_server_$dev.log" 2>&1 &
    pid=$!
    for _ in $(seq 100); do grep -q http:// "$LOG_DIR/view_server_$dev.log" && break; sleep 0.1; done
    run "view_${dev}_1280x720" python3 "$REPO/bench/view_latency.py" --port "$port" --frames "$VIEW_FRAMES" --size 1280x720 ||
      failed=1
    run "view_${dev}_426x240" python3 "$REPO/bench/view_latency.py" --port "$port" --frames "$VIEW_FRAMES" --size 426x240 ||
      failed=1
    kill -INT "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    local preview
    preview=$(sed -nE 's/^latency .*median ([0-9.]+) ms.*/\1/p' "$LOG_DIR/view_${dev}_426x240.log")
    [ -n "$preview" ] && note "# view on $dev: dragging (426x240 previews, one at a time) at $(awk -v l="$preview" 'BEGIN { printf "%.1f", 1000 / l }') frames/s"
  done
  return "$failed"
}

{
  echo "# run_gpu.sh $(date -u +%FT%TZ): parts ${PARTS[*]}; $VS"
  echo "# DEVICE=$DEVICE CELLS=$CELLS STEPS=$STEPS RENDER_CELLS=$RENDER_CELLS RENDER_DEVICES='$RENDER_DEVICES' RENDER_SIZES='$RENDER_SIZES'"
  echo "# STREAM_SIZE=$STREAM_SIZE STREAM_STEPS='$STREAM_STEPS' LEVELS='$LEVELS' STREAM_ARGS='$STREAM_ARGS' DEMO_ARGS='$DEMO_ARGS'"
  echo "# DATA_DIR=$DATA_DIR: $(($(free_bytes) / 1000000000)) GB free; streamed demo about $(($(demo_bytes "$CELLS" "$STEPS") / 1000000000)) GB, rendered about $(($(demo_bytes "$RENDER_CELLS" 1) / 1000000000)) GB"
  echo "# $(nproc) cores, $(free -g | awk '/^Mem:/ { print $2 " GiB memory" }'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
  if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader | sed 's/^/# GPU: /'
  else
    echo "# no nvidia-smi"
  fi
} | tee -a "$SUMMARY"

status=0
for part in "${PARTS[@]}"; do
  note "## part $part"
  # A subshell outside any condition, so that set -e stops the part at its first failure.
  set +e
  (set -e; "part_$part")
  rc=$?
  set -e
  if [ "$rc" != 0 ]; then
    note "## part $part FAILED (exit status $rc)"
    status=1
  else
    note "## part $part done"
  fi
done
if [ "${CLEAN_DATA:-0}" = 1 ]; then
  rm -rf "$STREAM_DS" "$RENDER_DS"
  note "# removed $STREAM_DS $RENDER_DS (CLEAN_DATA=1)"
fi
note "# run_gpu.sh finished $(date -u +%FT%TZ), status $status; logs in $LOG_DIR"
exit "$status"
