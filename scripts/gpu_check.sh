#!/usr/bin/env bash
# On a GPU machine: builds with CUDA, runs the whole suite (the CUDA tests run instead of
# skipping), and the GPU benchmarks; logs go to the folder given as the first argument.
set -uo pipefail
cd "$(dirname "$0")/.."
LOG_DIR="${1:?usage: scripts/gpu_check.sh LOG_DIR}"
mkdir -p "$LOG_DIR"
{
  nvidia-smi || true
  git rev-parse HEAD 2>/dev/null || true
} >"$LOG_DIR/machine.txt" 2>&1
BUILD_DIR=build-gpu bash scripts/build.sh -DVOLSTREAM_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES="${CUDA_ARCH:-90}" \
  >"$LOG_DIR/build.log" 2>&1 || { echo "build failed, see $LOG_DIR/build.log"; exit 1; }
ctest --test-dir build-gpu --output-on-failure -j4 >"$LOG_DIR/tests.log" 2>&1
status=$?
if [ -x bench/run_gpu.sh ]; then bash bench/run_gpu.sh build-gpu/volstream "$LOG_DIR" >"$LOG_DIR/bench.log" 2>&1; fi
tail -5 "$LOG_DIR/tests.log"
exit $status
