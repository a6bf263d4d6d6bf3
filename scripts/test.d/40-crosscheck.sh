#!/usr/bin/env bash
# Cross-check against FCL and Bullet (issue 4): builds examples-c/crosscheck (glcollide, FCL
# and Bullet from Debian, CGAL as the exact judge; packages in 40-crosscheck.deps) and runs
# every scene. Exit status non-zero on any glcollide disagreement with the exact reference
# (the peers' disagreements are printed as findings only). Extra arguments go to the
# program, e.g. `bash scripts/test.d/40-crosscheck.sh --only colon --frames 20`.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --locked -q
make -s -C examples-c/crosscheck -j"$(nproc)"
examples-c/crosscheck/build/crosscheck --meshes ../shared/meshes "$@"
