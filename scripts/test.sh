#!/usr/bin/env bash
# Quick start, second command (and what CI runs): installs what is missing, builds, and runs
# the whole test suite through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
cmake --preset default
cmake --build --preset default
ctest --preset default -j "$(nproc)"
