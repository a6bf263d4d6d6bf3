#!/usr/bin/env bash
# Every benchmark in one command (docs/PERFORMANCE.md):
#   bash scripts/bench.sh [--quick] [--scale X] [--no-gl] [--only NAME] [--budget SECONDS]
# Installs the peers' Debian packages only when missing, builds the library (release),
# the C++ peer program (bench/peers: its driver; the engines, scenes and exact answer are the
# peer harness in examples-c/peers, shared with the cross-check) and the parry bench, then runs:
#   1. bench/peers/build/glcol_peers: glcollide (C API; CPU, and GL_SELECT / GL_COMPUTE on a
#      headless EGL context when there is one) against FCL, Bullet and Embree on the same
#      scenes and frames, the epsilon sweep and the polygons-per-box sweep -> peers.csv;
#   2. benches/parry.rs on the same frames (dumped by 1) -> parry.csv, memory_rust.csv;
#   3. benches/refit.rs -> refit.md, and benches/gl.rs -> gl.md (GL backends, no host draws,
#      read-backs per query; skipped with --no-gl);
#   4. bench/summarize.py -> SUMMARY.md, results.json and the SVG figures.
# Output: $BENCH_OUT (default bench-results/). Meshes: $MESHES (default ../shared/meshes).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${BENCH_OUT:-bench-results}
meshes=${MESHES:-../shared/meshes}
bash scripts/deps.sh libfcl-dev libbullet-dev libembree-dev libcgal-dev libgmp-dev libmpfr-dev python3
mkdir -p "$out"
scenes=$(mktemp -d)
trap 'rm -rf "$scenes"' EXIT
echo "== build"
cargo build --release --locked -q
make -s -C bench/peers LIBDIR="${CARGO_TARGET_DIR:-$PWD/target}/release"
{
  echo "start: $(date -u +%FT%TZ) load: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "nproc: $(nproc)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  echo "kernel: $(uname -r)"
  echo "git: $(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD -- src 2>/dev/null || echo ' (src has uncommitted changes)')"
  echo "args: $*"
} >"$out/machine.txt"
echo "== glcol_peers $*"
bench/peers/build/glcol_peers --meshes "$meshes" --out "$out" --dump "$scenes" "$@"
echo "== parry"
cargo bench --locked -q --bench parry -- "$scenes" "$out/parry.csv"
echo "== refit"
frames=200
for a in "$@"; do [ "$a" = --quick ] && frames=5; done
cargo bench --locked -q --bench refit -- "$frames" >"$out/refit.md"
gl_frames=40
for a in "$@"; do
  [ "$a" = --quick ] && gl_frames=3
  [ "$a" = --no-gl ] && gl_frames=0
done
if [ "$gl_frames" -gt 0 ]; then
  echo "== gl"
  cargo bench --locked -q --bench gl -- "$gl_frames" >"$out/gl.md"
fi
echo "end: $(date -u +%FT%TZ) load: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/machine.txt"
python3 bench/summarize.py "$out"
echo "wrote $out/SUMMARY.md"
