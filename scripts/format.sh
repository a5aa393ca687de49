#!/usr/bin/env bash
# Code style (doc/install.md "Code style"): .clang-format and .clang-tidy at the repository root.
#   scripts/format.sh            reformat every C++ file in place (review the diff before committing)
#   scripts/format.sh --check    list what clang-format would change, per module; exit 1 if anything
#   scripts/format.sh --tidy [MODULE...]   clang-tidy over the modules' sources (needs build/compile_commands.json);
#                                          exit 1 if a warning remains in a product module
# Needs Debian's clang-format and clang-tidy (apt-get install clang-format clang-tidy).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
modules=(support calibration metrology mechanism datasets pipeline report apps python tests benchmarks examples fuzz)
mode="${1:-}"

case "$mode" in
  "")
    git ls-files '*.cpp' '*.hpp' | xargs clang-format -i
    ;;
  --check)
    status=0
    for module in "${modules[@]}"; do
      files=0; lines=0
      while IFS= read -r file; do
        changed=$(clang-format "$file" | diff "$file" - | grep -c '^<' || true)
        if [ "$changed" -gt 0 ]; then files=$((files + 1)); lines=$((lines + changed)); fi
      done < <(git ls-files "$module/*.cpp" "$module/*.hpp")
      printf '%-12s %4d files, %5d lines clang-format would change\n' "$module" "$files" "$lines"
      [ "$files" -eq 0 ] || status=1
    done
    exit $status
    ;;
  --tidy)
    # One clang-tidy process at a time (heavy); exit 1 when a product module (not tests,
    # benchmarks, examples) keeps a warning or an error, so CI can run it.
    shift
    [ -f build/compile_commands.json ] || { echo "format.sh: configure build/ first (scripts/build.sh)" >&2; exit 2; }
    (($#)) && modules=("$@")
    product=" support calibration metrology mechanism datasets apps "
    status=0
    for module in "${modules[@]}"; do
      mapfile -t files < <(git ls-files "$module/*.cpp")
      ((${#files[@]})) || continue
      log="build/clang-tidy-$module.log"
      rc=0
      clang-tidy -p build --quiet "${files[@]}" >"$log" 2>/dev/null || rc=$?
      count=$(grep -cE '(warning|error):' "$log" || true)
      printf '%-12s %5d clang-tidy warnings (%s)%s\n' "$module" "$count" "$log" "$( ((rc)) && echo ", clang-tidy failed: exit $rc")"
      [[ ("$count" -eq 0 && "$rc" -eq 0) || "$product" != *" $module "* ]] || status=1
    done
    exit $status
    ;;
  *)
    echo "usage: scripts/format.sh [--check | --tidy [MODULE...]]" >&2
    exit 2
    ;;
esac
