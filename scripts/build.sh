#!/usr/bin/env bash
# Installs what building mire needs (scripts/setup.sh), then configures and builds it in build/
# (Release with line tables), warnings as errors (MIRE_WERROR, off by default for users).
# MIRE_TARGET=name builds that target and what it needs only (the demo builds `mire`); extra
# arguments go to cmake. Prints the build's wall time (doc/install.md).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh"
start=$(date +%s)
cmake -S "$root" -B "$root/build" -G Ninja -DMIRE_WERROR=ON "$@" >/dev/null
cmake --build "$root/build" -j "$(nproc)" ${MIRE_TARGET:+--target "$MIRE_TARGET"}
echo "build: ${MIRE_TARGET:-all} in $(( $(date +%s) - start )) s" >&2
