#!/usr/bin/env bash
# One hash of everything a build reads (sources, tests, CMake files), the same wherever the tree
# is: scripts/gpu_prebuild.sh stamps its archive with it, and scripts/gpu_check.sh unpacks the
# archive only onto a tree that hashes the same. Files are hashed by content, not by git (the
# device tool's copy names another commit than the tree it carries).
set -euo pipefail
cd "$(dirname "$0")/.."
# Python's byte-code caches (tests run here write them) are not sources.
find CMakeLists.txt src apps tests fuzz python -name __pycache__ -prune -o -type f -print |
  LC_ALL=C sort |
  xargs -d '\n' sha256sum | sha256sum | cut -d' ' -f1
