#!/usr/bin/env bash
# Issue 6: memory safety of the C side. The C examples run under valgrind with zero errors
# and zero definite or indirect leaks ("still reachable" is not a leak: the Rust runtime
# keeps a few process-lifetime allocations such as thread-local message buffers).
# Needs the C examples built (scripts/test.sh builds them first; this builds them if not).
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -x examples-c/build/api_errors ] && [ -x examples-c/build/deform_demo ] &&
  [ -x examples-c/build/readme_example ] || make -s -C examples-c
vg=(valgrind --quiet --error-exitcode=99 --leak-check=full
    --errors-for-leak-kinds=definite,indirect --show-leak-kinds=definite,indirect
    --track-origins=yes)
log=$(mktemp)
run() {
  echo "valgrind: $*"
  if ! "${vg[@]}" "$@" >"$log" 2>&1; then
    cat "$log"
    echo "valgrind found errors or leaks in: $*" >&2
    exit 1
  fi
  tail -1 "$log"
}
run examples-c/build/api_errors
run examples-c/build/readme_example
run examples-c/build/deform_demo data 3 0
run examples-c/build/deform_demo data 2 0.001
rm -f "$log"
echo "valgrind: no errors, no leaks"
