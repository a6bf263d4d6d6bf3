#!/usr/bin/env bash
# Cross-check against FCL and Bullet (issue 4): builds examples-c/crosscheck (its driver, on
# the peer harness examples-c/peers shared with the benchmark: glcollide, FCL and Bullet from
# Debian, CGAL as the exact judge; packages in 40-crosscheck.deps) and runs every scene. Exit status non-zero on any glcollide disagreement with the exact reference
# (the peers' disagreements are printed as findings only). Extra arguments go to the
# program, e.g. `bash scripts/test.d/40-crosscheck.sh --only colon --frames 20`.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -d ../shared/meshes ] || {
  echo "skipped: needs ../shared/meshes (the unbundled meshes: LGPL and 100k-triangle ones; CI has ../shared)"
  exit 0
}
cargo build --release --locked -q
make -s -C examples-c/crosscheck -j"$(nproc)"
bin=examples-c/crosscheck/build/crosscheck
# The checker must be able to fail: with one glcollide pair dropped per frame it has to say so.
rc=0
"$bin" --meshes ../shared/meshes --only "vertex touch" --frames 3 --inject >/dev/null || rc=$?
if [ "$rc" -ne 1 ]; then
  echo "crosscheck: self-test failed: a dropped glcollide pair gave exit status $rc, not 1" >&2
  exit 1
fi
"$bin" --meshes ../shared/meshes "$@"
