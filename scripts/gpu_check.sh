#!/usr/bin/env bash
# On a GPU machine: builds with CUDA, runs the whole suite (the CUDA tests run instead of
# skipping), and the GPU benchmarks (bench/run_gpu.sh); logs go to LOG_DIR.
#
# usage: scripts/gpu_check.sh LOG_DIR [PHASE...]      (the order of the arguments does not matter)
#   build         configure and build build-gpu with CUDA              -> LOG_DIR/build.log
#   test          ctest in build-gpu (needs the build phase)           -> LOG_DIR/tests.log
#   bench         bench/run_gpu.sh: data, stream, render, mesh, view   -> LOG_DIR/bench.log + its files
#   bench-data | bench-stream | bench-render | bench-mesh | bench-view   one part of bench each (bench.log appended)
#   all           build, test, bench (the default)
# On the device tool's machine (no -dev packages, no network), first here:
#   bash scripts/device_deps.sh fetch        (the .deb files into .devdeps, about 3 MB)
# then run with carry [".devdeps"]; the build phase unpacks them (DEPS_PREFIX, /opt/volstream-deps).
# To spend no device time on the build: `bash scripts/gpu_prebuild.sh` here first (about 17 minutes
# on 2 cores), and carry [".devdeps", ".gpuprebuilt"]: the build phase then unpacks that build when
# it was made from this tree's sources, and builds otherwise.
# Where one command may run only so long (e.g. 10 minutes), run one phase per command:
#   scripts/gpu_check.sh L build; scripts/gpu_check.sh L test;
#   scripts/gpu_check.sh L bench-data; scripts/gpu_check.sh L bench-stream; scripts/gpu_check.sh L bench-render
# and, should the stream benchmark still not fit, spread its levels over commands with
# LEVELS=baseline,async-io,... (bench/run_gpu.sh merges the runs). Environment: CUDA_ARCH (90),
# CTEST_JOBS (4), CTEST_TIMEOUT (600 s per test: a kernel that never ends must not stop the
# rest), and bench/run_gpu.sh's (CELLS, STEPS, DEVICE, ...).
set -uo pipefail
usage() { echo "usage: scripts/gpu_check.sh LOG_DIR [build|test|bench|bench-data|bench-stream|bench-render|bench-mesh|bench-view|all ...]" >&2; exit 2; }

LOG_DIR=""
PHASES=()
for arg in "$@"; do
  case $arg in
    build | test | bench | bench-data | bench-stream | bench-render | bench-mesh | bench-view | all) PHASES+=("$arg") ;;
    *) [ -z "$LOG_DIR" ] || usage; LOG_DIR="$arg" ;;
  esac
done
[ -n "$LOG_DIR" ] || usage
[ ${#PHASES[@]} -gt 0 ] || PHASES=(all)
EXPANDED=()
for p in "${PHASES[@]}"; do
  if [ "$p" = all ]; then EXPANDED+=(build test bench); else EXPANDED+=("$p"); fi
done
mkdir -p "$LOG_DIR" || exit 1
LOG_DIR="$(realpath "$LOG_DIR")"  # relative to the caller's directory, before the cd
cd "$(dirname "$0")/.." || exit 1
BUILD_DIR="${GPU_BUILD_DIR:-build-gpu}"  # GPU_BUILD_DIR: e.g. a CPU build, to try the bench phases elsewhere
{
  date -u +%FT%TZ
  nvidia-smi || true
  git rev-parse HEAD 2>/dev/null || true
} >"$LOG_DIR/machine.txt" 2>&1

# The lent machine has no Debian -dev packages and no network: when the run carries .devdeps
# (scripts/device_deps.sh fetch, here), they are unpacked and CMake looks there first.
phase_build() {
  local deps=() prefix=""
  : >"$LOG_DIR/build.log"
  if [ -d .devdeps ]; then
    prefix="$(bash scripts/device_deps.sh install .devdeps "${DEPS_PREFIX:-/opt/volstream-deps}")" || return 1
    deps=(-DCMAKE_PREFIX_PATH="$prefix")
    echo "dependencies from .devdeps, unpacked in $prefix" >>"$LOG_DIR/build.log"
  fi
  unpack_prebuilt "$prefix" >>"$LOG_DIR/build.log" 2>&1 && return 0
  BUILD_DIR=$BUILD_DIR bash scripts/build.sh -DVOLSTREAM_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES="${CUDA_ARCH:-90}" \
    "${deps[@]}" >>"$LOG_DIR/build.log" 2>&1 || { echo "build failed, see $LOG_DIR/build.log"; return 1; }
}

# scripts/gpu_prebuild.sh's archive (carried as .gpuprebuilt), when it was built from the sources of
# this tree at this path: unpacked instead of a build. Its programs were linked here against
# Debian's libraries, which the GPU machine has only from .devdeps, and CUDA's runtime by soname:
# prebuilt_env.sh, beside them, puts both folders on the loader's path for every phase.
unpack_prebuilt() {
  local prefix="$1" archive=.gpuprebuilt/build-gpu.tar.gz stamp here
  [ -f "$archive" ] && [ "$BUILD_DIR" = build-gpu ] || return 1
  stamp="$(tar -xzOf "$archive" build-gpu/prebuilt_sources.sha256)" || return 1
  here="$(bash scripts/gpu_source_hash.sh; pwd)"
  if [ "$stamp" != "$here" ]; then
    echo "prebuilt archive not used: built from other sources or another path ($(echo $stamp | cut -c1-12) against $(echo $here | cut -c1-12))"
    return 1
  fi
  rm -rf build-gpu && tar -xzf "$archive" || return 1
  local cuda_lib
  cuda_lib="$(dirname "$(dirname "$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)")")/lib64"
  echo "export LD_LIBRARY_PATH=\"${prefix:+$prefix/lib/x86_64-linux-gnu:}$cuda_lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}\"" \
    >build-gpu/prebuilt_env.sh
  # A library the machine lacks would fail every test: then build instead.
  if ! (source build-gpu/prebuilt_env.sh && build-gpu/volstream --help >/dev/null); then
    echo "prebuilt volstream does not start here: building instead"
    rm -rf build-gpu
    return 1
  fi
  echo "prebuilt build-gpu unpacked from $archive (sources $(echo $stamp | cut -c1-12)); no build"
}
use_prebuilt_env() { [ ! -f "$BUILD_DIR/prebuilt_env.sh" ] || source "$BUILD_DIR/prebuilt_env.sh"; }

phase_test() {
  use_prebuilt_env
  [ -x "$BUILD_DIR/volstream" ] || { echo "no $BUILD_DIR/volstream: run the build phase first"; return 1; }
  ctest --test-dir "$BUILD_DIR" --output-on-failure -j"${CTEST_JOBS:-4}" --timeout "${CTEST_TIMEOUT:-600}" >"$LOG_DIR/tests.log" 2>&1
  local status=$?
  tail -5 "$LOG_DIR/tests.log"
  return $status
}

# bench, bench-data, bench-stream, bench-render: bench/run_gpu.sh with the parts asked for.
phase_bench() {
  use_prebuilt_env
  [ -x "$BUILD_DIR/volstream" ] || { echo "no $BUILD_DIR/volstream: run the build phase first"; return 1; }
  local part="${1:-all}" before=0
  [ -f "$LOG_DIR/bench.log" ] && before=$(wc -l <"$LOG_DIR/bench.log")
  bash bench/run_gpu.sh "$BUILD_DIR/volstream" "$LOG_DIR" "$part" >>"$LOG_DIR/bench.log" 2>&1
  local status=$?
  tail -n +$((before + 1)) "$LOG_DIR/bench.log" | grep -E '^(## part|  -> (FAILED|TIMED OUT)|WARNING)' 
  return $status
}

status=0
for phase in "${EXPANDED[@]}"; do
  start=$(date +%s)
  case $phase in
    build) phase_build ;;
    test) phase_test ;;
    bench) phase_bench all ;;
    bench-*) phase_bench "${phase#bench-}" ;;
  esac
  rc=$?
  echo "gpu_check: $phase $([ $rc = 0 ] && echo ok || echo "FAILED ($rc)") in $(($(date +%s) - start)) s"
  if [ $rc != 0 ]; then
    status=1
    [ "$phase" = build ] && break  # nothing after it can run without the binary
  fi
done
exit $status
