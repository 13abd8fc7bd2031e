#!/usr/bin/env bash
# Unstructured meshes: volstream's CPU renderer against VTK's vtkUnstructuredGridVolumeRayCastMapper
# (python3-vtk9, offscreen under xvfb-run) on the same .vtu, same view, same transfer function,
# same image size (issue 12).
#
# For each mesh (demo tets with TETS elements, demo mixed with MIXED elements; 0 skips one) and
# each look in LOOKS (haze: a faint constant opacity at low densities fills the whole mesh and shows
# its outline, so every element is on some visible ray; blobs: the same without the haze, so
# empty-space skipping has something to skip):
#   1. volstream demo NAME --elements N --steps 1 --write-mesh NAME_N.vtu (once, reused)
#   2. volstream convert NAME_N.vtu: REPEATS timed runs (whole command; the dataset is removed first)
#   3. volstream info --json: bytes_per_element, resident bytes; one untimed render once the files
#      are 2 s old, so that the timed renders find the mesh's check stamp (io/check_stamp.h)
#   4. REPEATS rounds of: volstream render (whole command, and the render time it prints) and
#      bench/vtk_umesh_render.py (reader, tetrahedralisation if the mesh holds non-tetrahedra,
#      first render, second render = the steady state, whole script) in turn
#   5. png_compare.py on the last round's two images (RMSE in 8-bit units); the images and the
#      difference (x4) are copied to LOGS as umesh_vs_vtk_NAME_N_LOOK_{volstream,vtk,diff}.png
# Prints median [min..max] of every figure and a markdown table (OUT/table.md); everything the
# tools print goes to OUT/logs/ and the summary to LOGS/umesh_vs_vtk_<date>.log.
#
# usage: bench/umesh_vs_vtk.sh OUT_DIR [TETS=1e6] [MIXED=5e5]
#        FILES="A.vtu ..." (meshes of your own over the unit cube with a point field "density",
#        such as bench/make_refined_polyhedra.py's, each run as the demos are; 0 0 skips the demos)
#        VS=build/volstream REPEATS=3 SIZE=512x512 LOGS=bench/logs (where the log and images go)
#        LOOKS="haze blobs"
#        VTK_INTEGRATOR=auto (see vtk_umesh_render.py --integrator) VTK_RENDERS=2
#        ENCODING=reference (convert --encoding: the figures in RESULTS.md are the reference's)
#        SPLIT=0 (1: convert --split-into-tets, volstream renders the mesh split into tets as VTK
#        does; the rows say "split")
# Installs python3-vtk9, xvfb and xauth with apt-get when they are missing (apt-get update first).
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/.." && pwd)"
OUT="$1"
TETS="${2:-1e6}"
MIXED="${3:-5e5}"
VS="$(realpath "${VS:-$REPO/build/volstream}")"
REPEATS="${REPEATS:-3}"
SIZE="${SIZE:-512x512}"
LOGS="${LOGS:-$REPO/bench/logs}"
LOOKS=(${LOOKS:-haze blobs})
VTK_INTEGRATOR="${VTK_INTEGRATOR:-auto}"
VTK_RENDERS="${VTK_RENDERS:-2}"
ENCODING="${ENCODING:-reference}"
SPLIT="${SPLIT:-0}"
SPLIT_ARGS=()
[ "$SPLIT" = 1 ] && SPLIT_ARGS=(--split-into-tets)
PY=/usr/bin/python3

# The view and the transfer function, given to both renderers in the same words. The Gaussian
# blobs of the demos' density field are the bright part; the haze look adds a faint constant
# opacity at low densities that shows the mesh's outline (a check of the framing).
FIELD=density
RANGE=0.02,1.1
opacity_of() { case "$1" in
  haze) echo 0.02:0.004,0.15:0.004,0.5:0.03,1.1:0.12 ;;
  blobs) echo 0.02:0,0.15:0,0.5:0.03,1.1:0.12 ;;
  *) echo "unknown look $1" >&2; exit 2 ;;
esac; }
UNIT=0.01
CAM_POS=2.3,1.6,2.9
CAM_AT=0.5,0.5,0.5
CAM_UP=0,1,0
FOV=35
BG=0.06,0.06,0.08
VIEW=(--field "$FIELD" --range "$RANGE" --unit-distance "$UNIT" --camera-pos "$CAM_POS"
  --camera-at "$CAM_AT" --camera-up "$CAM_UP" --fov "$FOV" --size "$SIZE" --background "$BG")

# --- dependencies ---------------------------------------------------------------------------------
missing=()
"$PY" -c 'import vtk' 2>/dev/null || missing+=(python3-vtk9)
command -v xvfb-run >/dev/null || missing+=(xvfb)
command -v xauth >/dev/null || missing+=(xauth)
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" = 0 ] || SUDO=sudo
  echo "installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

mkdir -p "$OUT/logs" "$LOGS"
OUT="$(realpath "$OUT")"
STAMP="$(date -u +%Y-%m-%d)"
SUMMARY="$LOGS/umesh_vs_vtk_${STAMP}.log"
exec > >(tee -a "$SUMMARY") 2>&1

# median / min / max of whitespace-separated numbers: "MED [MIN..MAX]"
stats() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{ v[NR] = $1 } END {
  if (NR == 0) { print "-"; exit }
  m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
  printf "%.3f [%.3f..%.3f]", m, v[1], v[NR] }'; }
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{ v[NR] = $1 } END {
  if (NR == 0) { print "nan"; exit }
  printf "%.4f", (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
jget() { "$PY" -c "import json,sys; d=json.load(open(sys.argv[1])); v=eval(sys.argv[2]); print(v)" "$@"; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4f", b - a }'; }
# ratio_of_medians A_VALUES B_VALUES: median(A) / median(B), two decimals.
ratio_of_medians() { awk -v a="$(echo "$1" | median)" -v b="$(echo "$2" | median)" 'BEGIN { printf "%.2f", a / b }'; }

echo "# $(date -u +%FT%TZ) umesh_vs_vtk: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'),"\
  "$(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo), load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# commit $(git -C "$REPO" rev-parse --short HEAD)$(git -C "$REPO" diff --quiet HEAD -- src apps 2>/dev/null || echo ' (+ uncommitted changes in src/apps)'),"\
  "binary $VS ($(stat -c %y "$VS" | cut -d. -f1), sha256 $(sha256sum "$VS" | cut -c1-12))"
echo "# VTK $("$PY" -c 'import vtk; print(vtk.vtkVersion.GetVTKVersion())'), integrator $VTK_INTEGRATOR, size $SIZE, repeats $REPEATS, encoding $ENCODING, split $SPLIT"
echo "# view: ${VIEW[*]}"
for look in "${LOOKS[@]}"; do echo "# look $look: --opacity $(opacity_of "$look")"; done

TABLE="$OUT/table.md"
{
  echo "| mesh | look | elements | convert s | B/element | volstream render s | volstream whole s | VTK read s | VTK tetrahedralize s | VTK 1st render s | VTK 2nd render s | VTK whole s | 2nd render VTK/volstream | whole VTK/volstream | VTK 2nd render / volstream whole (target 10) | peak RSS MiB volstream / VTK | RMSE (all / covered px) |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} >"$TABLE"

# run_mesh NAME N [VTU]: the demo NAME of N elements, or the given VTU (its rows named NAME).
run_mesh() {
  local name="$1" n="$2"
  local tag="${name}_${n}" vtu="$OUT/${name}_${n}.vtu" demo="$OUT/${name}_${n}.demo" ds="$OUT/${name}_${n}.vs"
  [ -z "${3:-}" ] || { tag="$name" vtu="$3" ds="$OUT/$name.vs"; }
  [ "$SPLIT" = 1 ] && tag="${tag}_split" ds="$OUT/${name}_${n}_split.vs"
  local L="$OUT/logs/$tag"
  mkdir -p "$L"
  if [ ! -f "$vtu" ]; then
    "$VS" demo "$name" --elements "$n" --steps 1 -o "$demo" --write-mesh "$vtu" -q >"$L/demo.log"
    rm -rf "$demo"
  fi
  echo
  echo "## $tag: $vtu ($(du -m "$vtu" | cut -f1) MiB)"

  # convert
  local conv=() t0 t1
  for ((i = 1; i <= REPEATS; ++i)); do
    rm -rf "$ds"
    t0=$(now)
    "$VS" convert "$vtu" -o "$ds" --encoding "$ENCODING" "${SPLIT_ARGS[@]}" >"$L/convert_$i.log" 2>&1
    t1=$(now)
    conv+=("$(elapsed "$t0" "$t1")")
  done
  "$VS" info "$ds" --json >"$L/info.json"
  local elements bpe resident
  elements=$(jget "$L/info.json" 'd["elements"]')
  bpe=$(jget "$L/info.json" '"%.1f" % d["bytes_per_element"]')
  resident=$(jget "$L/info.json" '"%.1f" % (d["resident_bytes"]["total"] / d["elements"])')
  echo "convert (whole command) s: $(echo "${conv[*]}" | stats)   [$(tail -1 "$L/convert_1.log")]"
  echo "elements $elements ($(jget "$L/info.json" 'd["elements_by_type"]')), bytes_per_element $bpe, resident bytes per element $resident"
  local conv_stats
  conv_stats="$(echo "${conv[*]}" | stats)"
  # A load checks files younger than 2 s again and does not stamp them (io/check_stamp.h), so the
  # first renders after the converts would check the mesh (0.1-0.4 s more): one untimed render
  # after the files settle, so that every timed render is the steady-state command that VTK's
  # second render is compared with.
  sleep 3
  "$VS" render "$ds" -o "$OUT/warmup.png" --tf viridis --device cpu "${VIEW[@]}" >"$L/warmup.log" 2>&1
  for look in "${LOOKS[@]}"; do run_look "$look"; done
}

# run_look LOOK: the render rounds of one look (uses run_mesh's locals: name tag vtu ds L ...).
run_look() {
  local look="$1" opacity
  opacity="$(opacity_of "$look")"
  local lt="${tag}_${look}"
  echo
  echo "### $tag, look $look (--opacity $opacity)"
  local vs_render=() vs_whole=() vs_rss=() vtk_read=() vtk_import=() vtk_pic=() vtk_tet=() vtk_first=() vtk_second=() vtk_whole=() vtk_rss=()
  local vs_png="$OUT/${lt}_volstream.png" vtk_png="$OUT/${lt}_vtk.png"
  for ((i = 1; i <= REPEATS; ++i)); do
    /usr/bin/time -f '%e %M %U %S' -o "$L/vs_time_${look}_$i" "$VS" render "$ds" -o "$vs_png" --tf viridis --device cpu \
      "${VIEW[@]}" --opacity "$opacity" >"$L/vs_render_${look}_$i.log" 2>&1
    vs_render+=("$(sed -nE 's/^render [0-9]+x[0-9]+: ([0-9.eE+-]+) ?s.*/\1/p' "$L/vs_render_${look}_$i.log" | head -1)")
    vs_whole+=("$(cut -d' ' -f1 "$L/vs_time_${look}_$i")")
    vs_rss+=("$(awk '{ printf "%.0f", $2 / 1024 }' "$L/vs_time_${look}_$i")")
    xvfb-run -a -s "-screen 0 1280x1024x24" /usr/bin/time -f '%e %M %U %S' -o "$L/vtk_time_${look}_$i" \
      "$PY" "$HERE/vtk_umesh_render.py" "$vtu" -o "$vtk_png" "${VIEW[@]}" --opacity "$opacity" \
      --integrator "$VTK_INTEGRATOR" --renders "$VTK_RENDERS" >"$L/vtk_${look}_$i.json" 2>"$L/vtk_${look}_$i.err"
    local J="$L/vtk_${look}_$i.json"
    vtk_read+=("$(jget "$J" '"%.4f" % d["read"]')")
    vtk_import+=("$(jget "$J" '"%.4f" % d["import"]')")
    vtk_pic+=("$(jget "$J" '"%.4f" % (d["read"] + d["tetrahedralize"] + d["render"][0])')")
    vtk_tet+=("$(jget "$J" '"%.4f" % d["tetrahedralize"]')")
    vtk_first+=("$(jget "$J" '"%.4f" % d["render"][0]')")
    vtk_second+=("$(jget "$J" '"%.4f" % d["render"][-1]')")
    vtk_whole+=("$(cut -d' ' -f1 "$L/vtk_time_${look}_$i")")
    vtk_rss+=("$(awk '{ printf "%.0f", $2 / 1024 }' "$L/vtk_time_${look}_$i")")
    echo "round $i: volstream render ${vs_render[-1]} s (whole ${vs_whole[-1]} s, $(awk '{ print $3 + $4 }' "$L/vs_time_${look}_$i") CPU s;" \
      "$(sed -nE 's/^render [0-9]+x[0-9]+: .*\(([0-9.]+)s CPU time\), ([0-9.]+ M samples).*/render CPU \1 s, \2/p' "$L/vs_render_${look}_$i.log"));" \
      "VTK import ${vtk_import[-1]}, read ${vtk_read[-1]}, tet ${vtk_tet[-1]}, renders $(jget "$J" '" ".join("%.3f" % x for x in d["render"])')," \
      "output $(jget "$J" '"%.3f" % d["output"]') s (whole ${vtk_whole[-1]} s, $(awk '{ print $3 + $4 }' "$L/vtk_time_${look}_$i") CPU s)"
  done
  local J1="$L/vtk_${look}_1.json"
  echo "VTK: $(jget "$J1" 'd["integrator"]'), $(jget "$J1" 'd["threads"]') threads, $(jget "$J1" 'd.get("tets", d["cells"])') cells rendered"
  [ ! -s "$L/vtk_${look}_1.err" ] || { echo "VTK stderr (round 1):"; head -5 "$L/vtk_${look}_1.err"; }

  local C="$L/compare_${look}.json"
  "$PY" "$HERE/png_compare.py" "$vs_png" "$vtk_png" --diff "$OUT/${lt}_diff.png" --json >"$C"
  cp "$vs_png" "$LOGS/umesh_vs_vtk_${lt}_volstream.png"
  cp "$vtk_png" "$LOGS/umesh_vs_vtk_${lt}_vtk.png"
  cp "$OUT/${lt}_diff.png" "$LOGS/umesh_vs_vtk_${lt}_diff.png"
  local rmse rmse_cov
  rmse=$(jget "$C" '"%.2f" % d["rmse"]')
  rmse_cov=$(jget "$C" '"%.2f" % d["rmse_covered"]')
  echo "image (volstream vs VTK, 8-bit sRGB units): $(jget "$C" '" ".join("%s %s" % (k, ("%.4g" % v) if isinstance(v, float) else v) for k, v in d.items())')"

  local r_second r_whole r_target
  r_second=$(ratio_of_medians "${vtk_second[*]}" "${vs_render[*]}")
  # The issue's target: volstream's whole command against VTK's second render.
  r_target=$(ratio_of_medians "${vtk_second[*]}" "${vs_whole[*]}")
  r_whole=$(ratio_of_medians "${vtk_whole[*]}" "${vs_whole[*]}")
  echo "volstream render s: $(echo "${vs_render[*]}" | stats), whole command s: $(echo "${vs_whole[*]}" | stats), peak RSS MiB: $(echo "${vs_rss[*]}" | median)"
  echo "VTK read s: $(echo "${vtk_read[*]}" | stats), tetrahedralize s: $(echo "${vtk_tet[*]}" | stats)"
  echo "VTK first render s: $(echo "${vtk_first[*]}" | stats), second render s: $(echo "${vtk_second[*]}" | stats)"
  echo "VTK read + tetrahedralize + first render s: $(echo "${vtk_pic[*]}" | stats) (import vtk: $(echo "${vtk_import[*]}" | stats))"
  echo "VTK whole script s: $(echo "${vtk_whole[*]}" | stats), peak RSS MiB: $(echo "${vtk_rss[*]}" | median)"
  echo "ratios of medians: second render VTK/volstream $r_second, whole VTK/volstream $r_whole, VTK second render / volstream whole $r_target"
  echo "| $name$([ "$SPLIT" = 1 ] && echo ' (split into tets)') | $look | $elements | $conv_stats | $bpe | $(echo "${vs_render[*]}" | stats) | $(echo "${vs_whole[*]}" | stats) |"\
    "$(echo "${vtk_read[*]}" | stats) | $(echo "${vtk_tet[*]}" | stats) | $(echo "${vtk_first[*]}" | stats) | $(echo "${vtk_second[*]}" | stats) |"\
    "$(echo "${vtk_whole[*]}" | stats) | $r_second | $r_whole | $r_target | $(echo "${vs_rss[*]}" | median | cut -d. -f1) / $(echo "${vtk_rss[*]}" | median | cut -d. -f1) |"\
    "$rmse / $rmse_cov |" >>"$TABLE"
}

[ "$TETS" = 0 ] || run_mesh tets "$TETS"
[ "$MIXED" = 0 ] || run_mesh mixed "$MIXED"
for file in ${FILES:-}; do run_mesh "$(basename "$file" .vtu)" file "$(realpath "$file")"; done
echo
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "(seconds: median [min..max] of $REPEATS runs; 'whole' = the whole process; RMSE in 8-bit sRGB units over RGB;"
echo " 'covered' = pixels where either image differs from its background)"
cat "$TABLE"
