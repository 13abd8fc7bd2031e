#!/usr/bin/env bash
# The whole test suite: installs dependencies, checks the formatting, builds Release with warnings
# as errors (with CUDA when nvcc is found) and runs every test, then builds with clang + AddressSanitizer + UndefinedBehaviorSanitizer and
# libFuzzer, and runs the suite again there, including a short run of every fuzz target.
# The MPI tests run against Open MPI and then MPICH (scripts/test_mpich.sh; VOLSTREAM_SKIP_MPICH=1
# skips it). Set VOLSTREAM_SKIP_SANITIZE=1 to run the Release suite only. The sanitizer build leaves MPI out:
# Open MPI's own allocations would fail LeakSanitizer; the Release suite runs the MPI tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/format.sh --check  # the tree is formatted (.clang-format)
BUILD_DIR=build bash scripts/build.sh -DVOLSTREAM_WERROR=ON
ctest --test-dir build --output-on-failure -j2 --timeout 900
# The MPI tests again against MPICH (its own build, about 3 minutes on 2 cores).
if [ "${VOLSTREAM_SKIP_MPICH:-0}" != 1 ]; then bash scripts/test_mpich.sh; fi
if [ "${VOLSTREAM_SKIP_SANITIZE:-0}" != 1 ]; then
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DVOLSTREAM_CUDA=OFF -DVOLSTREAM_SANITIZE=ON -DVOLSTREAM_FUZZ=ON -DVOLSTREAM_WERROR=ON \
    -DVOLSTREAM_PYTHON=OFF -DVOLSTREAM_MPI=OFF >/dev/null
  ninja -C build-asan
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    LSAN_OPTIONS="suppressions=$PWD/scripts/lsan_third_party.supp" \
    ctest --test-dir build-asan --output-on-failure -j2 --timeout 1800
fi
