#!/usr/bin/env bash
# Runs the scripted LSP session (session.test.js) under node's test runner, against the
# `moire` binary built beside it, with the pinned client libraries (package-lock.json).
#   run.sh MOIRE_BINARY WORK_DIR
# Exits 77 (ctest: skipped) when node or npm is missing, saying so.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../support/npm-modules.sh"
npm_modules "$here" "$2"
export MOIRE_BINARY="$1"
export MOIRE_SOURCE_DIR="$here/../.."
exec node --test "$here/session.test.js"
