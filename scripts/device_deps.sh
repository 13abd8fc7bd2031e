#!/usr/bin/env bash
# Build dependencies for the lent GPU machine (the `device` tool). That machine has CUDA, CMake,
# ninja and a C++ compiler, but none of Debian's -dev packages that volstream builds against,
# and it cannot download anything. So they are fetched here as .deb files into a folder that
# travels with the working tree (name it in the run's `carry`), and unpacked there into a prefix
# that CMake searches before the system (scripts/gpu_check.sh does this when the folder exists).
# Header-only packages, static test libraries and a few shared libraries (about 3 MB); the
# shared ones need glibc 2.34 and libstdc++ 3.4.21 or newer. Nothing is unpacked into /.
#
# usage: scripts/device_deps.sh fetch [DIR]              here, with Debian's archive reachable:
#                                                        the .deb files into DIR (default .devdeps)
#        scripts/device_deps.sh install [DIR] [PREFIX]   there: unpacks DIR into PREFIX (default
#                                                        /opt/volstream-deps) and prints the
#                                                        CMAKE_PREFIX_PATH to build with
set -euo pipefail
cd "$(dirname "$0")/.."
PACKAGES=(
  libcli11-dev nlohmann-json3-dev                                        # command line, manifests
  libtbb-dev libtbb12 libtbbmalloc2 libtbbbind-2-5 libhwloc15            # TBB (its CMake config names them all)
  libpng-dev libpng16-16 zlib1g-dev                                      # PNG, zlib
  liblz4-dev liblz4-1 liblzma-dev liblzma5                               # .vtu's LZ4 and LZMA blocks
  libgtest-dev libgmock-dev                                              # tests
  libcivetweb-dev libcivetweb1 libturbojpeg0-dev libturbojpeg0           # `volstream view`
)

fetch() {
  local dir="$1"
  mkdir -p "$dir"
  dir="$(realpath "$dir")"
  rm -f "$dir"/*.deb
  # apt-get download writes into the current directory.
  (cd "$dir" && apt-get download "${PACKAGES[@]}" >/dev/null)
  echo "fetched $(ls "$dir"/*.deb | wc -l) packages ($(du -sh "$dir" | cut -f1)) into $dir"
}

# Development symlinks that point at an absolute path of Debian's layout (libz.so ->
# /lib/x86_64-linux-gnu/libz.so.1.2.13) are pointed at the machine's own library of that name,
# or removed (CMake then links the static library beside them).
relink_absolute() {
  local prefix="$1" link target name found
  while IFS= read -r link; do
    target="$(readlink "$link")"
    [[ "$target" == /* ]] || continue
    [ -e "$prefix$target" ] && { ln -sf "$prefix$target" "$link"; continue; }
    name="$(basename "$link")"  # libz.so: the machine's libz.so.N
    found="$(ls /lib/x86_64-linux-gnu/"$name".* /usr/lib/x86_64-linux-gnu/"$name".* 2>/dev/null | head -1 || true)"
    if [ -n "$found" ]; then ln -sf "$found" "$link"; else rm -f "$link"; fi
  done < <(find "$prefix" -type l)
}

install_deps() {
  local dir="$1" prefix="$2"
  ls "$dir"/*.deb >/dev/null 2>&1 || { echo "device_deps.sh: no .deb files in $dir (run fetch first)" >&2; exit 2; }
  mkdir -p "$prefix"
  for deb in "$dir"/*.deb; do dpkg-deb -x "$deb" "$prefix"; done
  relink_absolute "$prefix"
  echo "$prefix/usr"
}

case "${1:-}" in
  fetch) fetch "${2:-.devdeps}" ;;
  install) install_deps "${2:-.devdeps}" "${3:-/opt/volstream-deps}" ;;
  *) echo "usage: scripts/device_deps.sh fetch [DIR] | install [DIR] [PREFIX]" >&2; exit 2 ;;
esac
