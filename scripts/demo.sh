#!/usr/bin/env bash
# Installs dependencies, builds, installs the Python module and renders the built-in jet demo to
# out/demo.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=build bash scripts/build.sh
# The Python module, when it was built (pybind11 found): installed for /usr/bin/python3 so that
# `import volstream` works from anywhere (cmake --install puts it in the interpreter's site directory).
if ls build/python/volstream*.so >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
  $SUDO cmake --install build --component python >/dev/null
  echo "python: /usr/bin/python3 -c 'import volstream' (docs/python.md)"
fi
mkdir -p out
./build/volstream render --demo jet -o out/demo.png
echo "image: $(pwd)/out/demo.png"
