#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (build-fuzz/, -DMIRE_FUZZ=ON) and runs each
# on its seed corpus (fuzz/corpus/<name>/, files from datasets/specs and small CSVs), either
# for a time budget or for a number of executions:
#   bash scripts/fuzz.sh            # 20 s per target (CI)
#   bash scripts/fuzz.sh -t 60      # 60 s per target
#   bash scripts/fuzz.sh -n 1000000 # 10^6 executions per target (benchmark; doc/robustness.md)
# A crash, a sanitizer report, a leak-free timeout (> 10 s on one input) or an out-of-memory
# (> 2 GB) fails the run; the input that caused it is kept in build-fuzz/findings/.
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
bash "$root/scripts/setup.sh" --tests
command -v clang++ >/dev/null || { echo "fuzz: clang++ is missing (scripts/setup.sh --tests installs clang)" >&2; exit 1; }
# -O1 without debug info: the instrumented Ceres/Eigen code of mechanism/ compiles several times
# faster than at -O2 -g, and parsers run fast enough (ASan still names the functions).
cmake -S "$root" -B "$root/build-fuzz" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DMIRE_FUZZ=ON \
  -DMIRE_BUILD_TESTS=OFF -DMIRE_BUILD_BENCHMARKS=OFF -DMIRE_PYTHON=OFF -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g0" >/dev/null
cmake --build "$root/build-fuzz" --target fuzzers -j "$(nproc)"
findings="$root/build-fuzz/findings"
mkdir -p "$findings"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
failed=0
for corpus in "$root"/fuzz/corpus/*/; do
  name="$(basename "$corpus")"
  work="$root/build-fuzz/corpus/$name"   # grows as the fuzzer learns; the seeds stay untouched
  mkdir -p "$work"
  limit=(-max_total_time="$seconds")
  [ -n "$runs" ] && limit=(-runs="$runs")
  start=$(date +%s)
  if "$root/build-fuzz/fuzz/fuzz_$name" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=4096 \
      -artifact_prefix="$findings/$name-" -print_final_stats=1 "$work" "$corpus" >"$root/build-fuzz/$name.log" 2>&1; then
    status=ok
  else
    status=FAILED
    failed=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$root/build-fuzz/$name.log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz $name: $status, $execs executions in $(( $(date +%s) - start )) s (log build-fuzz/$name.log)"
  [ "$status" = ok ] || tail -40 "$root/build-fuzz/$name.log"
done
exit "$failed"
