#!/usr/bin/env bash
# The main job: install what the `mire` command needs, build it (that target only), and run
# `mire demo` on the bundled default data.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
MIRE_TARGET=mire bash "$root/scripts/build.sh"
"$root/build/apps/mire" demo -o "${MIRE_DEMO_OUT:-$root/demo-output}" "$@"
