#!/usr/bin/env bash
# Quick start, second command: installs what is missing, builds, runs the whole test suite
# through ctest, and says how many tests were skipped and why (a test that cannot run all of
# itself here, tests/support/Skip.h). Arguments go to the configure step:
#   scripts/test.sh -DMOIRE_WERROR=ON     (what CI runs, through .ci/run; the option then
#                                          stays in build/'s cache until -DMOIRE_WERROR=OFF)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
cmake --preset default "$@"
cmake --build --preset default
status=0
ctest --preset default -j "$(nproc)" 2>&1 | tee build/ctest.log || status=$?

# ctest lists the skipped tests under "The following tests did not run"; their reasons are
# the "skipped: ..." messages in the log of the run.
skipped=$(grep -c ' (Skipped)$' build/ctest.log || true)
echo "test.sh: $skipped test(s) skipped"
if [[ $skipped -gt 0 ]]; then
  grep -ho 'skipped: .*' build/Testing/Temporary/LastTest.log | sort | uniq -c | sort -rn |
    sed 's/^/  /'
fi
exit $status
