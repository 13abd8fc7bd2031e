#!/usr/bin/env bash
# Formats every C++/CUDA source with the project's .clang-format; --check only reports (exit 1
# when a file would change), as scripts/test.sh does.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.cu' '*.cuh')
if [ "${1:-}" = --check ]; then
  clang-format --dry-run --Werror "${files[@]}"
else
  clang-format -i "${files[@]}"
fi
