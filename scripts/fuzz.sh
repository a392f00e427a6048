#!/usr/bin/env bash
# Runs moire's libFuzzer targets (fuzz/, docs/fuzzing.md) from a build of the default preset.
#
#   scripts/fuzz.sh TARGET [SECONDS]          one campaign (default 300 s), in the foreground
#   scripts/fuzz.sh --all [--seconds N]       every target at once, each under nice (default 1800 s)
#   scripts/fuzz.sh --runs N [--seed S] [--fresh] TARGET    a bounded run (what ctest runs)
#   scripts/fuzz.sh --list                    the targets
# Options: --build DIR (default build), --jobs N (with --all: at most N at a time).
#
# A campaign keeps its corpus in BUILD/fuzz/corpus/TARGET (it grows from one campaign to the
# next) and writes what it finds (crash-*, timeout-*, oom-*, leak-*) to BUILD/fuzz/findings/TARGET;
# a finding becomes a regression case by moving it to fuzz/regressions/TARGET/. Every campaign
# also reads the seed corpus (BUILD/fuzz/seeds) and the regression cases.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
targets=(parse sema lower autodiff spirv render format)

# Limits shared by every run. -max_len matches fuzz::kMaxInput; -timeout is per input (the
# slowest target, render, needs well under a second on the seeds); -rss_limit_mb catches
# memory blow-ups. LeakSanitizer stays on, with third-party leaks suppressed.
max_len=4096
per_input_timeout=20
rss_limit_mb=2048

build="$root/build" seconds="" runs="" seed="" fresh=0 all=0 jobs=${#targets[@]} target=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build="$(cd "$2" && pwd)"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --fresh) fresh=1; shift ;;
    --all) all=1; shift ;;
    --jobs) jobs="$2"; shift 2 ;;
    --list) printf '%s\n' "${targets[@]}"; exit 0 ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) if [[ -z "$target" ]]; then target="$1"; else seconds="$1"; fi; shift ;;
  esac
done

bin="$build/fuzz-libfuzzer/bin"
seeds="$build/fuzz/seeds"
if [[ ! -d "$seeds" ]]; then
  echo "fuzz.sh: no seed corpus in $seeds: configure and build the default preset first" >&2
  exit 2
fi

export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/fuzz/lsan.supp:print_suppressions=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

# run TARGET: one libFuzzer process; its output goes to stdout.
run() {
  local t="$1" exe="$bin/moire_fuzz_$1"
  if [[ ! -x "$exe" ]]; then
    echo "fuzz.sh: $exe is not built (it needs clang-16 and libclang-rt-16-dev)" >&2
    return 2
  fi
  local corpus findings
  if [[ $fresh -eq 1 ]]; then
    findings="$(mktemp -d "${TMPDIR:-/tmp}/moire-fuzz-$t.XXXXXX")"
    corpus="$findings/corpus"
  else
    corpus="$build/fuzz/corpus/$t"
    findings="$build/fuzz/findings/$t"
  fi
  mkdir -p "$corpus" "$findings"
  local args=(-max_len=$max_len -timeout=$per_input_timeout -rss_limit_mb=$rss_limit_mb
              -print_final_stats=1 -artifact_prefix="$findings/" -dict="$root/fuzz/moire.dict")
  [[ -n "$runs" ]] && args+=(-runs="$runs")
  [[ -n "$seconds" ]] && args+=(-max_total_time="$seconds")
  [[ -n "$seed" ]] && args+=(-seed="$seed")
  local rc=0
  "$exe" "${args[@]}" "$corpus" "$seeds" "$root/fuzz/regressions/$t" || rc=$?
  if [[ $rc -ne 0 ]]; then
    echo "fuzz.sh: $t found something (exit $rc); the input is in $findings/" >&2
  elif [[ $fresh -eq 1 ]]; then
    rm -rf "$findings"
  fi
  return $rc
}

if [[ $all -eq 0 ]]; then
  if [[ -z "$target" || ! " ${targets[*]} " =~ " $target " ]]; then
    echo "fuzz.sh: name a target (${targets[*]}) or --all" >&2
    exit 2
  fi
  [[ -z "$runs" && -z "$seconds" ]] && seconds=300
  run "$target"
  exit
fi

# --all: every target in the background under nice, a log each; then a summary.
[[ -z "$runs" && -z "$seconds" ]] && seconds=1800
logs="$build/fuzz/logs"
mkdir -p "$logs"
echo "fuzz.sh: ${targets[*]} for ${seconds:-?} s each, $jobs at a time; logs in $logs/"
declare -A pids
for t in "${targets[@]}"; do
  while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do wait -n || true; done
  extra=()
  [[ -n "$runs" ]] && extra+=(--runs "$runs")
  [[ -n "$seconds" ]] && extra+=(--seconds "$seconds")
  [[ -n "$seed" ]] && extra+=(--seed "$seed")
  [[ $fresh -eq 1 ]] && extra+=(--fresh)
  nice -n 10 "$0" --build "$build" "${extra[@]}" "$t" >"$logs/$t.log" 2>&1 &
  pids[$t]=$!
done
status=0
printf '%-9s %6s %12s %10s  %s\n' target exit executions 'exec/s' 'new features, corpus'
for t in "${targets[@]}"; do
  rc=0
  wait "${pids[$t]}" || rc=$?
  [[ $rc -ne 0 ]] && status=1
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$logs/$t.log" | grep -o '[0-9]*$' || echo '?')
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$logs/$t.log" | grep -o '[0-9]*$' || echo '?')
  last=$(grep -E '^#[0-9]+' "$logs/$t.log" | tail -1 | grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' || true)
  printf '%-9s %6s %12s %10s  %s\n' "$t" "$rc" "${execs:-?}" "${rate:-?}" "$last"
done
exit $status
