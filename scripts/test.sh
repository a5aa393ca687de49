#!/usr/bin/env bash
# Set up, build everything (the tests, the benchmarks and the Python module included), and run the
# whole test suite with ctest.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh" --tests
bash "$root/scripts/build.sh" -DMIRE_BUILD_TESTS=ON -DMIRE_BUILD_BENCHMARKS=ON -DMIRE_PYTHON=ON
cd "$root/build"
ctest --output-on-failure -j "$(nproc)" "$@"
