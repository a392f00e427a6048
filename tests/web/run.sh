#!/usr/bin/env bash
# Runs one browser test file (node's test runner) against the system Chromium, driven by the
# pinned puppeteer-core (package-lock.json), installed with `npm ci` into WORK_DIR once per lockfile.
#   run.sh MOIRE_BINARY WORK_DIR TEST_FILE
# Exits 77 (ctest: skipped) with the reason when node, npm or Chromium is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
moire=$1
work=$2
test_file=$3
for tool in node npm; do
  if ! command -v "$tool" >/dev/null; then
    echo "skipped: $tool is not installed (scripts/deps.sh installs nodejs and npm)"
    exit 77
  fi
done
chrome=${MOIRE_CHROMIUM:-$(command -v chromium || true)}
if [[ -z "$chrome" ]]; then
  echo "skipped: chromium is not installed (scripts/deps.sh installs it)"
  exit 77
fi
mkdir -p "$work"
# One install at a time: several test files share WORK_DIR and ctest runs them in parallel.
exec 9>"$work/.install.lock"
flock 9
if ! cmp -s "$here/package-lock.json" "$work/package-lock.json" || [[ ! -d "$work/node_modules" ]]; then
  cp "$here/package.json" "$here/package-lock.json" "$work/"
  (cd "$work" && npm ci --prefer-offline --no-audit --no-fund --loglevel=error)
fi
flock -u 9
export MOIRE_BINARY="$moire"
export MOIRE_SOURCE_DIR="$here/../.."
export MOIRE_CHROMIUM="$chrome"
export NODE_PATH="$work/node_modules"
exec node --test "$here/$test_file"
