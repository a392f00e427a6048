#!/usr/bin/env bash
# Fails when a C++ source of the tree is not as clang-format makes it (.clang-format), naming
# each such file. CI runs it (.ci/run). One version of clang-format, the LLVM toolchain's 16,
# decides: versions differ in small ways, and a check that passes on one machine and fails on
# another is worse than none.
#   scripts/check-format.sh         checks, changing nothing; exit status 1 on drift
#   scripts/check-format.sh --fix   formats every such file in place
# CLANG_FORMAT names another binary.
set -euo pipefail
cd "$(dirname "$0")/.."
clang_format=${CLANG_FORMAT:-clang-format-16}
if ! command -v "$clang_format" >/dev/null; then
  echo "check-format: $clang_format is not installed (scripts/deps.sh installs it)" >&2
  exit 2
fi

# The sources: C++ and C under version control (a checkout without git: every such file but
# the build directories). Lexer.re is re2c's input, not C++, and the .def lists are macro
# tables laid out by hand; neither is checked.
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files -- '*.cpp' '*.h' '*.c')
else
  mapfile -t files < <(find . -path './build*' -prune -o \( -name '*.cpp' -o -name '*.h' -o \
    -name '*.c' \) -type f -print | sed 's|^\./||' | sort)
fi

if [[ "${1:-}" == "--fix" ]]; then
  "$clang_format" -i "${files[@]}"
  exit 0
fi

report=$(mktemp)
trap 'rm -f "$report"' EXIT
if "$clang_format" --dry-run -Werror "${files[@]}" 2>"$report"; then
  echo "check-format: ${#files[@]} files as $clang_format formats them"
  exit 0
fi
mapfile -t drifted < <(grep -oE '^[^:]+:[0-9]+:[0-9]+: error:' "$report" | cut -d: -f1 | sort -u)
if [[ ${#drifted[@]} -eq 0 ]]; then
  cat "$report" >&2 # clang-format failed for another reason: say what it said
  exit 2
fi
echo "check-format: ${#drifted[@]} of ${#files[@]} files differ from what $clang_format makes of them:" >&2
printf '  %s\n' "${drifted[@]}" >&2
echo "Format them with scripts/check-format.sh --fix (or $clang_format -i FILE)." >&2
exit 1
