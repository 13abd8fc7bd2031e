#!/usr/bin/env bash
# Installs dependencies, builds, and renders the built-in jet demo to out/demo.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=build bash scripts/build.sh
mkdir -p out
./build/volstream render --demo jet -o out/demo.png
echo "image: $(pwd)/out/demo.png"
