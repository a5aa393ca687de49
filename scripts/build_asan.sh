#!/usr/bin/env bash
# Configures and builds the one instrumented build, build-asan/: clang, ASan + UBSan in every
# mire target, libFuzzer coverage in the libraries (-DMIRE_SANITIZE=ON -DMIRE_FUZZ=ON). The
# sanitized test suite (scripts/sanitize.sh) and the fuzz targets (scripts/fuzz.sh) both run
# from it, so CI compiles mire twice, not three times. Arguments: targets to build (default all).
# -O1 with line tables only: instrumented Ceres/Eigen code compiles several times faster than
# at -O2 -g, and ASan reports still name the function, file and line.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh"
command -v clang++ >/dev/null || { echo "build_asan: clang++ is missing (scripts/setup.sh installs clang)" >&2; exit 1; }
cmake -S "$root" -B "$root/build-asan" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
  -DMIRE_SANITIZE=ON -DMIRE_FUZZ=ON -DMIRE_BUILD_BENCHMARKS=OFF -DMIRE_PYTHON=OFF \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" >/dev/null
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build "$root/build-asan" -j "$(nproc)" "${targets[@]}"
