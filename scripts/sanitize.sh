#!/usr/bin/env bash
# Builds mire with AddressSanitizer + UndefinedBehaviorSanitizer (-DMIRE_SANITIZE=ON, gcc, -O1
# with minimal debug info, in build-asan/) and runs the test suite there: the bad-input matrix
# first (its binary is built first; the matrix must complete), then every other test within what is left of a suite-level budget
# (MIRE_SANITIZE_BUDGET seconds, default 1800; shortened to end by MIRE_SANITIZE_DEADLINE, a Unix
# time, when given). Any sanitizer report or failed test fails the run; tests the budget stops or
# leaves unstarted are counted, not failed. Extra arguments go to both
# ctest calls (e.g. -R Detection). Cost: doc/robustness.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
budget="${MIRE_SANITIZE_BUDGET:-1800}"
per_test=900  # s; a test killed before this was stopped by the budget, not hung
start=$(date +%s)
bash "$root/scripts/setup.sh" --tests
# -O1 -g1: the instrumented Ceres/Eigen code compiles far faster than at -O2 -g and ASan still
# names function, file and line. NDEBUG as in the default build, so the same code is tested.
cmake -S "$root" -B "$root/build-asan" -G Ninja -DMIRE_SANITIZE=ON -DMIRE_BUILD_BENCHMARKS=OFF -DMIRE_PYTHON=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" >/dev/null
# The bad-input matrix's binary first, so the matrix runs before the rest is compiled.
cmake --build "$root/build-asan" -j "$(nproc)" --target mire_apps_tests
echo "sanitize: build of the bad-input matrix took $(( $(date +%s) - start )) s"
cd "$root/build-asan"
# Leaks are not checked: OpenCV, ViSP and Ceres keep process-lifetime allocations that LSan
# reports at exit; every other ASan/UBSan finding aborts the process (and fails the test).
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:halt_on_error=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
tests_start=$(date +%s)
if [ -n "${MIRE_SANITIZE_DEADLINE:-}" ] && [ $(( MIRE_SANITIZE_DEADLINE - tests_start )) -lt "$budget" ]; then
  budget=$(( MIRE_SANITIZE_DEADLINE - tests_start ))
fi
ctest --output-on-failure -j "$(nproc)" --timeout "$per_test" -R '^BadInput/' "$@"
cmake --build "$root/build-asan" -j "$(nproc)"
echo "sanitize: build of everything took $(( $(date +%s) - start )) s"
left=$(( budget - ($(date +%s) - tests_start) ))
if [ "$left" -le 60 ]; then
  echo "sanitize: the bad-input matrix passed; NO OTHER TEST RAN: ${left} s of the ${budget} s budget left" >&2
  exit 0
fi
# The rest, within the budget: ctest --stop-time starts no test after that time and kills the
# running ones ("***Timeout" before the per-test limit); only those are forgiven below.
# ctest reads the stop time as a time of day: past midnight, the budget is not applied.
stop=(--stop-time "$(date -d "+${left} seconds" +%H:%M:%S)")
[ "$(date -d "+${left} seconds" +%j)" = "$(date +%j)" ] || stop=()
status=0
ctest --output-on-failure -j "$(nproc)" --timeout "$per_test" -E '^BadInput/' "${stop[@]}" "$@" | tee ctest-rest.log || status=$?
total=$(ctest -N -E '^BadInput/' "$@" | sed -n 's/^Total Tests: //p')
passed=$(grep -c ' Passed ' ctest-rest.log || true)
# "***Timeout   123.45 sec": stopped by the budget when shorter than the per-test limit.
read -r stopped hung < <(awk -v limit="$((per_test - 1))" '/\*\*\*Timeout/ {
  for (i = 2; i <= NF; i++) if ($i == "sec") { if ($(i - 1) < limit) s++; else h++ } } END { print s + 0, h + 0 }' ctest-rest.log)
echo "sanitize: tests took $(( $(date +%s) - tests_start )) s; of $total other tests $passed passed," \
  "$stopped were stopped and $(( total - passed - stopped )) not started by the ${budget} s budget, or failed"
[ "$status" -eq 0 ] && exit 0
# Anything that ended neither passed nor stopped by the budget fails the run.
if [ "$hung" -gt 0 ] || grep -E '\*\*\*(Failed|Exception)|SEGFAULT|Subprocess aborted|Child aborted' ctest-rest.log >/dev/null; then
  exit 1
fi
echo "sanitize: budget reached; every test that ended passed"
