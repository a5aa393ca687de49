#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ (in build-asan/, scripts/build_asan.sh) and runs each
# on its seed corpus (fuzz/corpus/<name>/, files from datasets/specs and small CSVs), either
# for a time budget or for a number of executions:
#   bash scripts/fuzz.sh            # 20 s per target (CI)
#   bash scripts/fuzz.sh -t 60      # 60 s per target
#   bash scripts/fuzz.sh -n 1000000 # 10^6 executions per target (benchmark; doc/robustness.md)
# A crash, a sanitizer report, a leak-free timeout (> 10 s on one input) or an out-of-memory
# (> 2 GB) fails the run; the input that caused it is kept in build-asan/findings/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds=20
runs=""
while getopts "t:n:" option; do
  case "$option" in
    t) seconds="$OPTARG" ;;
    n) runs="$OPTARG" ;;
    *) echo "usage: $0 [-t seconds | -n executions]" >&2; exit 2 ;;
  esac
done
bash "$root/scripts/build_asan.sh" fuzzers
build="$root/build-asan"
findings="$build/findings"
mkdir -p "$findings"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
failed=0
for corpus in "$root"/fuzz/corpus/*/; do
  name="$(basename "$corpus")"
  work="$build/corpus/$name"   # grows as the fuzzer learns; the seeds stay untouched
  mkdir -p "$work"
  limit=(-max_total_time="$seconds")
  [ -n "$runs" ] && limit=(-runs="$runs")
  start=$(date +%s)
  if "$build/fuzz/fuzz_$name" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=4096 \
      -artifact_prefix="$findings/$name-" -print_final_stats=1 "$work" "$corpus" >"$build/$name.log" 2>&1; then
    status=ok
  else
    status=FAILED
    failed=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/$name.log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz $name: $status, $execs executions in $(( $(date +%s) - start )) s (log build-asan/$name.log)"
  [ "$status" = ok ] || tail -40 "$build/$name.log"
done
exit "$failed"
