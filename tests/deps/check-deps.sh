#!/usr/bin/env bash
# Every Debian package that owns a file the configured build uses must be installed by
# scripts/deps.sh: listed there, pulled in by what is listed, or part of every Debian system
# (Essential or Priority: required, what a minimal install holds). Otherwise a fresh machine
# fails where this one passes, as it did when glslang's CMake package named glslangValidator
# and deps.sh did not install glslang-tools. Needs no network: dpkg and apt's local cache only.
#
#   check-deps.sh collect BUILD_DIR SOURCE_DIR OUT   lists the files the build uses in OUT
#   check-deps.sh check USED [LIST]                  checks them against LIST (default:
#                                                    scripts/deps.sh --list); fails naming
#                                                    each file and the package it is in
#   check-deps.sh expect-missing USED PACKAGE FILE   checks against deps.sh's list without
#                                                    PACKAGE and passes only if that fails
#                                                    naming FILE and PACKAGE (a self-test)
#
# The files, one "KIND PATH" a line in OUT:
#   header  every system header in the compile dependencies (ninja -t deps)
#   ninja   every absolute path in build.ninja and rules.ninja: libraries linked, the compiler,
#           re2c, the files whose change reruns the configure
#   lib     every shared library the built programs load (ldd)
#   loaded  every shared library moire loads at run time to list the Vulkan devices (the
#           loader's drivers and layers, through dlopen)
#   cmake   every file a configure reads, and every file an imported target names, which
#           CMake requires to exist (cmake --trace-expand of a configure of the same source in
#           a scratch directory). Files a find module merely probes for and the build does not
#           use (zlib.h for LLVM's optional zlib) are not counted.
#   tool    the programs the tests and the runtime run, from TOOLS below
set -euo pipefail

# Programs run by the tests, by moire itself and by CI, found on PATH: clip and its tests
# (ffmpeg, ffprobe), the viewer's tests (Xvfb, xdotool under timeout), the Vulkan device list
# test, which compares `moire devices` with vulkaninfo, and CI's format check
# (clang-format-16, scripts/check-format.sh), and the editor packages' tests (node and npm for
# the VS Code extension, vim for the Vim package: editors/test/run-test.sh).
TOOLS=(ffmpeg ffprobe Xvfb xdotool timeout vulkaninfo clang-format-16 node npm vim)

here=$(cd "$(dirname "$0")" && pwd)
source_dir=$(cd "$here/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Lines of PATHS that name an existing file outside the project, made absolute.
system_files() {
  local build=$1 p
  while read -r p; do
    [[ "$p" == /* ]] || continue
    [[ "$p" == "$source_dir"/* || "$p" == "$build"/* ]] && continue
    if [[ -f "$p" ]]; then printf '%s\n' "$p"; fi
  done
}

collect() {
  local build source out
  build=$(cd "$1" && pwd)
  source=$(cd "$2" && pwd)
  out=$3
  local ninja
  ninja=$(sed -n 's/^CMAKE_MAKE_PROGRAM:[A-Z]*=//p' "$build/CMakeCache.txt")
  {
    # Headers: ninja's dependency log holds every header each object was compiled against.
    "$ninja" -C "$build" -t deps | sed -n 's/^    //p' | sort -u | system_files "$build" |
      sed 's/^/header /'
    # Every absolute path in the build's rules: libraries linked, the compiler, archiver and
    # re2c, and the files whose change reruns the configure. A compiler launcher (ccache) is
    # the developer's choice, not the build's need.
    local launchers
    launchers=$(sed -n 's/^CMAKE_[A-Z]*_COMPILER_LAUNCHER:[A-Z]*=//p' "$build/CMakeCache.txt")
    cat "$build/build.ninja" "$build/CMakeFiles/rules.ninja" | tr ' ;"$:' '\n\n\n\n\n' | sort -u |
      grep -vxF -e "${launchers:-/}" | system_files "$build" | sed 's/^/ninja /'
    # Shared libraries the programs load, including those loaded through others.
    { find "$build/bin" -maxdepth 1 -type f -perm -u+x -exec ldd {} + 2>/dev/null || true; } |
      sed -n 's/.*=> \(\/[^ ]*\) .*/\1/p' | sort -u | system_files "$build" | sed 's/^/lib /'
    # And those loaded at run time (dlopen): the Vulkan loader's drivers and layers, found
    # while moire lists the devices.
    { LD_DEBUG=files "$build/bin/moire" devices 2>&1 >/dev/null || true; } |
      sed -n 's/.*calling init: \(\/[^ ]*\).*/\1/p' | sort -u | system_files "$build" |
      sed 's/^/loaded /'
    # A configure of the same source, traced with every argument expanded. Options that
    # change what is found are copied from the build's cache.
    local options=()
    for var in CMAKE_BUILD_TYPE MOIRE_SANITIZE MOIRE_BUILD_TESTS MOIRE_BUILD_BENCH; do
      local value
      value=$(sed -n "s/^$var:[A-Z]*=//p" "$build/CMakeCache.txt")
      if [[ -n "$value" ]]; then options+=("-D$var=$value"); fi
    done
    cmake -S "$source" -B "$tmp/build" -G Ninja "${options[@]}" --trace-expand \
      --trace-redirect="$tmp/trace" >"$tmp/configure.log" 2>&1 ||
      { cat "$tmp/configure.log" >&2; echo "check-deps: the traced configure failed" >&2; exit 1; }
    # The files it read (each trace line starts with its file), and the files imported
    # targets name, which CMake requires to exist (the check lists of CMake's exports).
    {
      sed -n 's/^\(\/[^(]*\)([0-9]*):.*/\1/p' "$tmp/trace"
      grep -E '^[^ ]*\([0-9]+\): +list\(APPEND (_cmake_import_check_files_for_|_IMPORT_CHECK_FILES_FOR_)' \
        "$tmp/trace" | sed 's/^[^ ]*): *list(APPEND [^ ]* //; s/ )$//' | tr ' ;' '\n\n'
    } | sort -u | system_files "$tmp/build" | sed 's/^/cmake /'
    # Programs the tests run; each must be on PATH here, or the tests that need it skip.
    for tool in "${TOOLS[@]}"; do
      local at
      at=$(command -v "$tool") || { echo "check-deps: '$tool' is not on PATH" >&2; echo "tool /missing/$tool"; continue; }
      echo "tool $at"
    done
  } >"$tmp/used"
  if grep -q '^tool /missing/' "$tmp/used"; then
    echo "check-deps: install the packages of scripts/deps.sh (scripts/deps.sh as root)" >&2
    exit 1
  fi
  sort -u "$tmp/used" >"$out"
}

# The other spelling of a path across Debian's merged /usr (/lib is /usr/lib), or the path.
merged() {
  case "$1" in
    /usr/bin/* | /usr/sbin/* | /usr/lib/* | /usr/lib32/* | /usr/lib64/* | /usr/libx32/*) echo "${1#/usr}" ;;
    /bin/* | /sbin/* | /lib/* | /lib32/* | /lib64/* | /libx32/*) echo "/usr$1" ;;
    *) echo "$1" ;;
  esac
}

check() {
  local used=$1 list=${2:-}
  if [[ -n "$list" ]]; then
    sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' "$list" >"$tmp/listed"
  else
    "$source_dir/scripts/deps.sh" --list >"$tmp/listed"
  fi
  # What every Debian system has: Essential and required packages (mmdebstrap's minbase).
  dpkg-query -W -f='${Package} ${Essential} ${Priority} ${db:Status-Status}\n' |
    awk '$4 == "installed" && ($2 == "yes" || $3 == "required") { print $1 }' >"$tmp/base"
  # Everything those pull in, as apt installs it (no recommends, as deps.sh installs).
  # shellcheck disable=SC2046
  apt-cache depends --recurse --installed --no-recommends --no-suggests --no-conflicts \
    --no-breaks --no-replaces --no-enhances $(cat "$tmp/listed" "$tmp/base") 2>/dev/null |
    grep -v '^[ <]' | sort -u >"$tmp/closure"
  # shellcheck disable=SC2046
  dpkg-query -L $(cat "$tmp/closure") 2>/dev/null | grep '^/' | sort -u >"$tmp/owned" || true

  # Each used file with its other spellings: as used, across merged /usr, and resolved.
  cut -d' ' -f2- "$used" >"$tmp/paths"
  xargs -d '\n' realpath -e -- <"$tmp/paths" >"$tmp/real"
  paste -d' ' "$used" "$tmp/real" >"$tmp/pairs"
  awk -v owned="$tmp/owned" '
    function merged(p) {
      if (p ~ /^\/usr\/(bin|sbin|lib|lib32|lib64|libx32)\//) return substr(p, 5)
      if (p ~ /^\/(bin|sbin|lib|lib32|lib64|libx32)\//) return "/usr" p
      return p
    }
    BEGIN { while ((getline line < owned) > 0) have[line] = 1 }
    {
      kind = $1; path = $2; real = $3
      if (have[path] || have[merged(path)] || have[real] || have[merged(real)]) next
      print kind, path, real
    }' "$tmp/pairs" >"$tmp/unowned"

  # Name the package of each file left over; files in no package (a compiler's generated
  # files, /usr/local) are not deps.sh's business.
  local failures=0 kind path real
  while read -r kind path real; do
    local owner=""
    for p in "$path" "$(merged "$path")" "$real" "$(merged "$real")"; do
      owner=$(dpkg-query -S "$p" 2>/dev/null | grep -v '^diversion' | head -1 | sed 's/: .*//') && [[ -n "$owner" ]] && break
    done
    [[ -n "$owner" ]] || continue
    owner=${owner%%:*}
    echo "$path ($kind) is in package '$owner', which scripts/deps.sh neither lists nor pulls in"
    failures=$((failures + 1))
  done <"$tmp/unowned"
  local files
  files=$(wc -l <"$used")
  if ((failures > 0)); then
    echo "check-deps: $failures of $files files used by the build belong to packages scripts/deps.sh does not install; add them to its list"
    return 1
  fi
  echo "check-deps: all $files files used by the build come from packages scripts/deps.sh installs ($(wc -l <"$tmp/closure") packages with what they pull in)"
}

expect_missing() {
  local used=$1 package=$2 file=$3
  local list=$tmp/without-$package out
  "$source_dir/scripts/deps.sh" --list | grep -vxF "$package" >"$list"
  if out=$(check "$used" "$list"); then
    echo "check-deps self-test: without '$package' the check passed; it should fail naming $file"
    return 1
  fi
  printf '%s\n' "$out"
  if ! grep -F "$file" <<<"$out" | grep -qF "'$package'"; then
    echo "check-deps self-test: without '$package' the check failed, but not naming $file in '$package'"
    return 1
  fi
  echo "check-deps self-test: without '$package' the check fails naming $file, as it should"
}

case "${1:-}" in
  collect) collect "$2" "$3" "$4" ;;
  check) check "$2" "${3:-}" ;;
  expect-missing) expect_missing "$2" "$3" "$4" ;;
  *) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 2 ;;
esac
