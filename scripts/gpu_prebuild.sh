#!/usr/bin/env bash
# Here, before a session spends its lent GPU time: builds the CUDA configuration that
# scripts/gpu_check.sh would build on the GPU machine, and packs what its test and bench phases
# run into .gpuprebuilt/build-gpu.tar.gz (about 15 MB), so that the device's few minutes go to
# running, not compiling (its CUDA builds took 200-250 s of a 900 s budget). nvcc compiles here;
# nothing CUDA runs here.
#
# usage: scripts/gpu_prebuild.sh        (about 17 minutes on 2 cores; then carry [".devdeps",
#                                        ".gpuprebuilt"] with scripts/gpu_check.sh LOG build test ...)
# Environment: CUDA_ARCH (90), GPU_BUILD_DIR (build-gpu).
#
# The archive holds the build folder without its objects, stamped with a hash of the sources it
# was built from (scripts/gpu_source_hash.sh); gpu_check.sh's build phase unpacks it only when the
# tree it runs on hashes the same, and builds as before otherwise. The configuration is the one
# the GPU machine can run: no Python module, no MPI, no NetCDF or CGNS (none of them is there),
# and the tree's absolute paths, which the device tool keeps (the checkout's path here).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${GPU_BUILD_DIR:-build-gpu}"
OUT_DIR=.gpuprebuilt
NVCC="$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)"
[ -x "$NVCC" ] || { echo "gpu_prebuild.sh: no nvcc (on PATH or at /usr/local/cuda/bin)" >&2; exit 2; }

# IGNORE: a value that find_path keeps (it searches again over a -NOTFOUND) and if() reads as false.
BUILD_DIR=$BUILD_DIR bash scripts/build.sh -DVOLSTREAM_CUDA=ON -DCMAKE_CUDA_COMPILER="$NVCC" \
  -DCMAKE_CUDA_ARCHITECTURES="${CUDA_ARCH:-90}" -DVOLSTREAM_WERROR=ON -DVOLSTREAM_PYTHON=OFF -DVOLSTREAM_MPI=OFF \
  -DNETCDF_INCLUDE_DIR=IGNORE -DCGNS_INCLUDE_DIR=IGNORE

# The stamp: the sources' hash and the checkout's path (ctest's files name absolute paths).
{ bash scripts/gpu_source_hash.sh; pwd; } >"$BUILD_DIR/prebuilt_sources.sha256"
mkdir -p "$OUT_DIR"
# What ctest and bench/run_gpu.sh read: the executables and CTestTestfile.cmake files; not the
# objects, static libraries and ninja's state (a build on the device starts afresh anyway).
tar -czf "$OUT_DIR/build-gpu.tar.gz" --exclude='*.o' --exclude='*.a' --exclude=CMakeFiles --exclude='.ninja_*' \
  --exclude=build.ninja --exclude=compile_commands.json --exclude=Testing "$BUILD_DIR"
echo "packed $BUILD_DIR ($(head -1 "$BUILD_DIR/prebuilt_sources.sha256" | cut -c1-12) of the sources) into" \
  "$OUT_DIR/build-gpu.tar.gz, $(du -h "$OUT_DIR/build-gpu.tar.gz" | cut -f1), in $SECONDS s"
