#!/usr/bin/env bash
# play, timeline and bench stream end to end: every pipeline level writes the same PNG frames,
# jumps give the frames of sequential play, the timeline is a Chrome trace that draws as an SVG,
# mid-stream errors stop with one line (naming the step) before that step's frame, mp4 via ffmpeg.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo jet --cells 10000 --steps 4 -o ds -q >/dev/null
R=(--size 48x32 -q)

for level in baseline async-io pinned direct-io preordered refit overlap; do
  mkdir -p "$level"
  "$VS" play ds --steps 0:4 --pipeline $level -o "$level/f_%02d.png" "${R[@]}" >"$level/log.txt"
  for i in 00 01 02 03; do
    cmp -s baseline/f_$i.png $level/f_$i.png || fail "$level frame $i differs from baseline"
  done
done
grep -q "played 4 frames at level overlap" overlap/log.txt || fail "no report: $(cat overlap/log.txt)"
grep -q "^render " overlap/log.txt || fail "no per-stage summary"
cmp -s baseline/f_00.png baseline/f_03.png && fail "steps 0 and 3 render the same image"
echo "ok: 7 levels x 4 frames identical"

# Jumps (and a stride) give the frames of sequential play.
mkdir -p jump stride
"$VS" play ds --steps 3,0,2 -o "jump/f_%d.png" "${R[@]}" >/dev/null
cmp -s jump/f_0.png baseline/f_03.png && cmp -s jump/f_1.png baseline/f_00.png && cmp -s jump/f_2.png baseline/f_02.png \
  || fail "jumped frames differ from sequential play"
"$VS" play ds --steps 1:4:2 --loop 2 -o "stride/f_%d.png" "${R[@]}" >/dev/null
[ "$(ls stride | wc -l)" = 4 ] || fail "stride with --loop 2: expected 4 frames"
cmp -s stride/f_3.png baseline/f_03.png || fail "strided frame differs"
echo "ok: jumps and strides"

# Timeline: valid Chrome trace JSON, drawn as SVG.
"$VS" play ds --pipeline overlap --timeline t.json "${R[@]}" >/dev/null
python3 - t.json <<'PY' || fail "timeline is not a valid Chrome trace"
import json, sys
events = json.load(open(sys.argv[1]))["traceEvents"]
x = [e for e in events if e["ph"] == "X"]
assert {e["name"] for e in x} == {"read", "upload", "ranges", "refit", "render", "output"}, x
assert all(e["dur"] >= 0 and isinstance(e["args"]["step"], int) for e in x)
assert len({e["tid"] for e in x}) == 2  # frame thread and loader
PY
"$VS" timeline t.json -o t.svg >/dev/null
head -c 4 t.svg | grep -q '<svg' && tail -1 t.svg | grep -q '</svg>' || fail "timeline SVG is not an SVG"
echo '{"traceEvents": [' >bad.json
expect_bad_input "timeline of broken JSON" timeline bad.json -o x.svg
expect_bad_input "timeline of a missing file" timeline nothere.json -o x.svg

# Mid-stream errors: one line naming the step, frames before it written, none for it.
f2=$(ls ds/fields/0_*/step_000002.f32)
for damage in missing truncated oversized; do
  rm -rf bad && cp -r ds bad && g="bad/${f2#ds/}"
  case $damage in
    missing) rm "$g" ;;
    truncated) truncate -s 1000 "$g" ;;
    oversized) truncate -s +8192 "$g" ;;
  esac
  for level in baseline async-io overlap; do
    rm -rf out && mkdir out
    expect_bad_input "$damage step file at $level" play bad --pipeline $level -o "out/f_%d.png" "${R[@]}"
    grep -q "step 2" "$WORK/err.txt" || fail "error does not name step 2"
    [ -f out/f_1.png ] && [ ! -e out/f_2.png ] && [ -z "$(ls out | grep -v '^f_[01].png$')" ] \
      || fail "$damage at $level: wrong frames written: $(ls out)"
  done
done

# The progress bar (forced on, stderr is no terminal here): complete at 100% after a good run; a
# run that fails part way ends the bar where it stopped, never at 100%, then the one error line.
VOLSTREAM_PROGRESS=always "$VS" play ds --steps 0:4 --size 48x32 >/dev/null 2>progress_ok.txt
grep -q "100.0%" progress_ok.txt || fail "progress bar of a good run not at 100%: $(cat -v progress_ok.txt)"
rm -rf bad && cp -r ds bad && rm "bad/${f2#ds/}"
for level in baseline overlap; do
  status=0
  VOLSTREAM_PROGRESS=always "$VS" play bad --steps 0:4 --pipeline $level --size 48x32 >/dev/null 2>progress.txt || status=$?
  [ "$status" = 2 ] || fail "progress test at $level: exit status $status, expected 2"
  grep -q "100" progress.txt && fail "a failed run shows 100% at $level: $(cat -v progress.txt)"
  grep -q "failed at frame 3/4" progress.txt || fail "no 'failed at frame 3/4' at $level: $(cat -v progress.txt)"
  tail -1 progress.txt | grep -q "^volstream: .*step 2" || fail "last line is not the error: $(tail -1 progress.txt)"
  echo "ok: progress at $level -> $(tr '\r' '\n' <progress.txt | grep 'failed at' | sed 's/\x1b\[K//')"
done

# Usage errors.
expect_bad_input "empty step range" play ds --steps 3:3
expect_bad_input "step out of range" play ds --steps 0,9
expect_bad_input "unknown level" play ds --pipeline warp
expect_bad_input "png pattern without %d" play ds -o frames.png "${R[@]}"

# Video through ffmpeg.
if command -v ffmpeg >/dev/null; then
  "$VS" play ds --steps 0:4 --loop 3 -o movie.mp4 "${R[@]}" >/dev/null
  [ -s movie.mp4 ] || fail "no mp4 written"
  if command -v ffprobe >/dev/null; then
    n=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 movie.mp4)
    [ "$n" = 12 ] || fail "mp4 has $n frames, expected 12"
  fi
  echo "ok: mp4"
fi

# bench stream: every level, a table, the same frames everywhere.
"$VS" bench stream ds --steps 0:3 --size 32x24 --timeline b.json >bench.txt 2>/dev/null || fail "bench stream failed: $(cat bench.txt)"
grep -q "frames identical at every level: yes" bench.txt || fail "bench: $(cat bench.txt)"
for level in baseline async-io pinned direct-io preordered refit overlap; do grep -q "^$level " bench.txt || fail "bench: no row $level"; done
"$VS" timeline b.json -o b.svg --rows stage >/dev/null
cat bench.txt
# Memory does not grow with the number of steps: 16 steps peak within 2 MiB of 2 steps, at the
# default level and at the baseline (one step of this series is 0.8 MiB; keeping each would add 11).
"$VS" demo jet --cells 2e5 --steps 16 --fields vorticity -o long -q >/dev/null
# Under AddressSanitizer freed blocks wait in a quarantine (resident) before reuse: turn it off here.
export ASAN_OPTIONS="${ASAN_OPTIONS:-}${ASAN_OPTIONS:+:}quarantine_size_mb=0"
for level in baseline overlap; do
  few=$("$VS" play long --steps 0:2 --pipeline $level --size 32x32 -q | awk '/^peak memory/ {print $3}')
  many=$("$VS" play long --steps 0:16 --pipeline $level --size 32x32 -q | awk '/^peak memory/ {print $3}')
  awk -v a="$few" -v b="$many" 'BEGIN { exit !(a > 0 && b - a < 2) }' || fail "$level: peak memory $few MiB for 2 steps, $many MiB for 16"
  echo "ok: $level peak memory $few MiB (2 steps), $many MiB (16 steps)"
done

echo "all stream CLI tests passed"
