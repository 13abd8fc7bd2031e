#!/usr/bin/env bash
# Installs every build, test and runtime dependency of volstream from Debian's packages.
# Safe to run repeatedly; needs root (or sudo).
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  clang libclang-rt-dev            # libFuzzer targets and the sanitizer build
  clang-format                     # the code style (.clang-format), checked by scripts/test.sh
  libcli11-dev nlohmann-json3-dev  # command line, manifests
  libtbb-dev                       # CPU threads (parallel_for)
  libpng-dev zlib1g-dev            # PNG output; zlib-compressed .vtu
  liblz4-dev liblzma-dev           # LZ4- and LZMA-compressed .vtu (VTK's other two compressors)
  libnetcdf-dev                    # Exodus II meshes (NetCDF files: io/exodus.h)
  libcgns-dev                      # CGNS meshes and solutions (io/cgns.h)
  libgtest-dev libgmock-dev        # tests
  ffmpeg                           # video output
  python3 pybind11-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  openmpi-bin libopenmpi-dev       # data-parallel rendering under mpirun (src/volstream/mpi/)
  mpich libmpich-dev               # the same against MPICH (scripts/test_mpich.sh; beside Open MPI,
                                   # which keeps mpicxx and mpirun)
  libcivetweb-dev libturbojpeg0-dev  # `volstream view`: HTTP/WebSocket server, JPEG frames
  chromium chromium-driver python3-selenium  # the viewer's browser test (headless)
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
