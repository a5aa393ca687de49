#!/usr/bin/env bash
# Configures and builds mire in build/ (Release with debug info), warnings as errors (MIRE_WERROR,
# off by default for users). Extra arguments go to cmake.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh"
cmake -S "$root" -B "$root/build" -G Ninja -DMIRE_WERROR=ON "$@" >/dev/null
cmake --build "$root/build" -j "$(nproc)"
