#!/usr/bin/env bash
# Configures and builds volstream (Release) in ./build. CUDA is compiled when nvcc is found.
# Extra arguments go to cmake (e.g. -DVOLSTREAM_CUDA=OFF).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${BUILD_DIR:-build}"
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
ninja -C "$BUILD_DIR"
