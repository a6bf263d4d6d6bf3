#!/usr/bin/env bash
# Self-collision against CGAL (issue 12, "Accuracy"): builds examples-c/selfcheck (C++17, only
# glcollide's header; CGAL 5.5 header-only, packages in 45-selfcheck.deps) and compares
# glcol_query_all's self pairs at epsilon 0 (threads 0 and 1, two leaf sizes, two creation
# orders) with CGAL::Polygon_mesh_processing::self_intersections (Epeck) on real simulation
# frames, the 92k-triangle crumpled cloth of bench/data (two frames, 78,000 pairs each), a
# tangled real cloth and adversarial folds, pushed and pinched vertices and sliver fans at
# scales 1e-4..1e4 and a 1e5 offset: equal sets or exit status 1 (about 1 minute).
# The checker must be able to fail first: with one glcollide pair dropped it has to say so.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -d ../shared/meshes/sim ] || {
  echo "skipped: needs ../shared/meshes/sim (the simulation frames; CI has ../shared)"
  exit 0
}
cargo build --release --locked -q
make -s -C examples-c/selfcheck
bin=examples-c/selfcheck/build/selfcheck
rc=0
"$bin" --meshes ../shared/meshes --only "pushed vertex (1.5" --inject >/dev/null 2>&1 || rc=$?
if [ "$rc" -ne 1 ]; then
  echo "selfcheck: self-test failed: a dropped glcollide pair gave exit status $rc, not 1" >&2
  exit 1
fi
"$bin" --meshes ../shared/meshes "$@" | tail -n 1
