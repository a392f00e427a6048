#!/usr/bin/env bash
# Runs one browser test file (node's test runner) against the system Chromium, driven by the
# pinned puppeteer-core (package-lock.json).
#   run.sh MOIRE_BINARY WORK_DIR TEST_FILE
# Exits 77 (ctest: skipped) with the reason when node, npm or Chromium is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
chrome=${MOIRE_CHROMIUM:-$(command -v chromium || true)}
if [[ -z "$chrome" ]]; then
  echo "skipped: chromium is not installed (scripts/deps.sh installs it)"
  exit 77
fi
source "$here/../support/npm-modules.sh"
npm_modules "$here" "$2"
export MOIRE_BINARY="$1"
export MOIRE_SOURCE_DIR="$here/../.."
export MOIRE_CHROMIUM="$chrome"
exec node --test "$here/$3"
