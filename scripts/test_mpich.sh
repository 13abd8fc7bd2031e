#!/usr/bin/env bash
# The MPI tests against MPICH (issue 17 asks for Open MPI and MPICH): builds volstream with
# MPICH's compiler wrapper in its own directory (default build-mpich; Debian's mpich and
# libmpich-dev install beside Open MPI as mpicxx.mpich and mpiexec.mpich, and leave `mpicxx` and
# `mpirun` to Open MPI), checks that the binary links MPICH and not Open MPI, and runs the MPI
# test (tests/mpi/render_ranks.sh) with mpiexec.mpich. Builds only the command line (no CUDA, no
# Python module): the MPI test needs nothing else. scripts/test.sh runs it after the Release
# suite: on 2 cores the build and the test take about 3 minutes (bench/logs/test_mpich.txt).
# Usage: scripts/test_mpich.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD="${1:-build-mpich}"
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DVOLSTREAM_MPI=ON -DVOLSTREAM_CUDA=OFF \
  -DVOLSTREAM_PYTHON=OFF -DVOLSTREAM_WERROR=ON -DMPI_CXX_COMPILER="$(command -v mpicxx.mpich)" \
  -DMPIEXEC_EXECUTABLE="$(command -v mpiexec.mpich)" >/dev/null
ninja -C "$BUILD" -j2 volstream
libs=$(ldd "$BUILD/volstream")
grep -q 'libmpich' <<<"$libs" || { echo "FAIL: $BUILD/volstream does not link MPICH" >&2; exit 1; }
if grep -q 'libmpi\.so' <<<"$libs"; then echo "FAIL: $BUILD/volstream links Open MPI" >&2; exit 1; fi
echo "$BUILD/volstream links $(grep -o 'libmpich[^ ]*' <<<"$libs" | head -1) ($(mpiexec.mpich --version | sed -nE 's/ *Version: *//p' | head -1))"
ctest --test-dir "$BUILD" -V -R '^mpi\.' --timeout 900
