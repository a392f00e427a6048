#!/usr/bin/env bash
# Quick start, first command: installs what is missing, builds into build/, and renders the
# embedded default scene to build/default.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
cmake --preset default
cmake --build --preset default
build/bin/moire render -o build/default.png
