#!/usr/bin/env bash
# Runs the scripted LSP session (session.test.js) under node's test runner, against the
# `moire` binary built beside it. The pinned client libraries (package-lock.json) are installed
# with `npm ci` into WORK_DIR, once per lockfile, from npm's cache when it has them.
#   run.sh MOIRE_BINARY WORK_DIR
# Exits 77 (ctest: skipped) when node or npm is missing, saying so.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
moire=$1
work=$2
for tool in node npm; do
  if ! command -v "$tool" >/dev/null; then
    echo "skipped: $tool is not installed (scripts/deps.sh installs nodejs and npm)"
    exit 77
  fi
done
mkdir -p "$work"
if ! cmp -s "$here/package-lock.json" "$work/package-lock.json" || [[ ! -d "$work/node_modules" ]]; then
  cp "$here/package.json" "$here/package-lock.json" "$work/"
  (cd "$work" && npm ci --prefer-offline --no-audit --no-fund --loglevel=error)
fi
export MOIRE_BINARY="$moire"
export MOIRE_SOURCE_DIR="$here/../.."
export NODE_PATH="$work/node_modules"
exec node --test "$here/session.test.js"
