#!/usr/bin/env bash
# The whole test suite under AddressSanitizer, LeakSanitizer and UndefinedBehaviorSanitizer:
# configures the preset `debug` (build-debug/, MOIRE_SANITIZE=ON), builds it and runs every
# test with ctest's preset `debug`, whose environment stops a test at the first error report
# (ASAN_OPTIONS, UBSAN_OPTIONS halt_on_error) and suppresses leaks inside third-party libraries
# only (LSAN_OPTIONS, tests/sanitizers/lsan.supp). Slow: on two cores about 35 minutes to
# build (no benchmarks) and 12 to run the suite.
#   scripts/sanitize.sh [ctest arguments]    e.g. scripts/sanitize.sh -R 'integration/view*'
# Build jobs: MOIRE_JOBS (default: the number of cores); it builds at low priority (nice).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
jobs=${MOIRE_JOBS:-$(nproc)}
cmake --preset debug
nice cmake --build --preset debug -j "$jobs"
ctest --preset debug -j "$jobs" "$@"
