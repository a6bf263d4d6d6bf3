#!/usr/bin/env bash
# Benchmark smoke run: every program of `scripts/bench.sh` on the small scenes with 3 frames
# (glcol_peers --quick, built from bench/peers and the peer harness examples-c/peers; GL
# backends left out: llvmpipe alone takes a minute under load), into a temporary directory.
# Checks that everything builds, runs, agrees with the exact answer and writes its files;
# asserts nothing about timing.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -d "${MESHES:-../shared/meshes}/sim" ] || {
  echo "skipped: needs ../shared/meshes (the benchmarks' meshes and simulation frames; CI has ../shared)"
  exit 0
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cargo build --release --locked -q
make -s -j2 -C bench/peers LIBDIR="${CARGO_TARGET_DIR:-$PWD/target}/release"
mkdir -p "$tmp/scenes"
bench/peers/build/glcol_peers --quick --no-gl --meshes "${MESHES:-../shared/meshes}" --out "$tmp" --dump "$tmp/scenes" 2>"$tmp/log" \
  || { cat "$tmp/log"; exit 1; }
# The contact-geometry cost bench (bench-results/contact.md), built and run on 2 frames.
make -s -j2 -C bench/contact LIBDIR="${CARGO_TARGET_DIR:-$PWD/target}/release"
bench/contact/build/contact_cost --meshes "${MESHES:-../shared/meshes}" --frames 2 --reps 1 --only colon >/dev/null 2>>"$tmp/log" \
  || { cat "$tmp/log"; exit 1; }
# The whole-scene peers (bench-results/scene.md): 2 frames of each scene; it fails when the
# pairs of Bullet or Embree (exact narrow phase) differ from glcollide's.
make -s -j2 -C bench/scene_peers LIBDIR="${CARGO_TARGET_DIR:-$PWD/target}/release"
bench/scene_peers/build/scene_peers --quick --meshes "${MESHES:-../shared/meshes}" >/dev/null 2>>"$tmp/log" \
  || { cat "$tmp/log"; exit 1; }
cargo bench --locked -q --bench parry -- "$tmp/scenes" "$tmp/parry.csv" 2>>"$tmp/log" || { cat "$tmp/log"; exit 1; }
echo "smoke" >"$tmp/machine.txt"
python3 bench/summarize.py "$tmp" >/dev/null
for f in peers.csv parry.csv memory_rust.csv SUMMARY.md results.json fig2_polygons_per_box.svg fig3_query_vs_size.svg speed_vs_error.svg; do
  [ -s "$tmp/$f" ] || { echo "bench smoke: $f missing"; exit 1; }
done
# exact configurations must give the exact answer (columns: engine 3, eps_rel 4, missed 16, extra 17)
bad=$(awk -F, 'NR > 1 && $4 == 0 && $16 != "" && ($16 != 0 || $17 != 0) && $3 !~ /gl_/ { print $1 " " $3 ": missed " $16 ", extra " $17 }' "$tmp/peers.csv" "$tmp/parry.csv")
if [ -n "$bad" ]; then
  echo "bench smoke: an exact configuration disagrees with the exact answer:"
  echo "$bad"
  exit 1
fi
echo "bench smoke: $(($(wc -l <"$tmp/peers.csv") - 1)) + $(($(wc -l <"$tmp/parry.csv") - 1)) runs, exact answers where expected"
