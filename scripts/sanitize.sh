#!/usr/bin/env bash
# Runs the whole test suite in the instrumented build (scripts/build_asan.sh: clang, ASan + UBSan)
# under a suite-level time budget (MIRE_SANITIZE_BUDGET seconds, default 1500). Any sanitizer
# report fails its test. Extra arguments go to ctest (e.g. -R BadInput). Cost: doc/robustness.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/build_asan.sh"
cd "$root/build-asan"
# Leaks are not checked: OpenCV, ViSP and Ceres keep process-lifetime allocations that LSan
# reports at exit; every other ASan/UBSan finding aborts the process (and fails the test).
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:halt_on_error=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
timeout "${MIRE_SANITIZE_BUDGET:-1500}" ctest --output-on-failure -j "$(nproc)" --timeout 900 "$@"
