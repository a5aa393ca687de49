#!/usr/bin/env bash
# The main job: set up, build, and run `mire demo` on the bundled default data.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/build.sh"
"$root/build/apps/mire" demo -o "${MIRE_DEMO_OUT:-$root/demo-output}" "$@"
