#!/usr/bin/env bash
# Contact geometry against CGAL's exact constructions (issue 13): builds
# examples-c/contact_check (public header + libglcollide; the peer harness for the meshes;
# CGAL Epeck as the reference; packages in 45-contact.deps) and checks every pair of the
# generated hard cases (coplanar, touching, slivers, near misses 1e-3..1e-7, offsets 1e3/1e5,
# scales 1e-4/1e4, degenerate; also placed by glcol_mesh_set_transform: f64 world positions;
# quads bent, bowtie, dart or degenerate, judged as the union of their triangles) and of real
# meshes. Exit status non-zero on any wrong flag,
# NaN, non-separating translation or error above 8 float ulps. About 15 s of CPU.
# Extra arguments go to the program, e.g. `bash scripts/test.d/45-contact.sh --only colon`.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -d ../shared/meshes/sim ] || {
  echo "skipped: needs ../shared/meshes/sim (the simulation frames; CI has ../shared)"
  exit 0
}
cargo build --release --locked -q
make -s -C examples-c/contact_check -j"$(nproc)"
bin=examples-c/contact_check/build/contact_check
# The checker must be able to fail: with one pair per family corrupted it has to say so.
rc=0
"$bin" --meshes ../shared/meshes --pairs 200 --frames 1 --inject >/dev/null || rc=$?
if [ "$rc" -ne 1 ]; then
  echo "contact_check: self-test failed: corrupted geometry gave exit status $rc, not 1" >&2
  exit 1
fi
"$bin" --meshes ../shared/meshes "$@"
