#!/usr/bin/env bash
# glcollide's exact continuous primitive tests (src/geom/ccd) beside Tight-Inclusion (TI, the
# conservative CCD of Wang et al. 2021, MIT, source in ../shared/peers/tight-inclusion) on the
# same queries: every vertex-face and edge-edge query of the exact ground truth of three
# simulation steps (../shared/meshes/sim/ccd), in one run (docs/PERFORMANCE.md):
#   bash scripts/bench-ccd-peers.sh
# 1. builds TI and its driver (bench/ccd_peers, g++ -O3 -DNDEBUG for both) into
#    target/peers/tight-inclusion/ (never linked into the library);
# 2. runs glcollide's ignored test `peer_columns` (src/geom/ccd/tests/bench.rs): ns per query,
#    false positives and negatives against the truth, the filter's share, and its tois;
# 3. runs the driver (TI with its authors' recommended settings), which also compares TI's
#    tois with glcollide's certified ones;
# 4. prints one markdown table of both.
# Both sides time the same way: the thread's CPU time, best of 3 runs of the whole set, each
# run repeated for at least 0.2 s. About 70 s of CPU once built, 1.5 min on a loaded 2-core VM
# (TI takes milliseconds on many of these near-contact queries); no timing is asserted.
set -euo pipefail
cd "$(dirname "$0")/.."
truth=../shared/meshes/sim/ccd
ti_src=../shared/peers/tight-inclusion
# CI and fresh clones have no ../shared: nothing to compare, not a failure.
for need in "$truth" "$ti_src/src/tight_inclusion/ccd.cpp"; do
  if [ ! -e "$need" ]; then
    echo "skipped: needs $need"
    exit 0
  fi
done
bash scripts/deps.sh libeigen3-dev libspdlog-dev libfmt-dev
build=${CARGO_TARGET_DIR:-$PWD/target}/peers/tight-inclusion

echo "== build" >&2
make -s -C bench/ccd_peers BUILD="$build" TI="$PWD/$ti_src"
cargo test --release --locked -q --lib --no-run

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
mkdir -p "$build/glc-toi"
echo "== glcollide" >&2
CCD_TOI_DIR="$build/glc-toi" cargo test --release --locked -q --lib \
  ccd::tests::bench::peer_columns -- --ignored --nocapture >"$build/glc.out"
# Only the test's own lines (cargo and the harness print theirs around them).
grep '^ccd-peers' "$build/glc.out" | cut -f2- >"$build/glc.tsv" || true
if [ ! -s "$build/glc.tsv" ]; then
  echo "bench-ccd-peers: glcollide printed no rows (see $build/glc.out)" >&2
  exit 1
fi
echo "== Tight-Inclusion" >&2
"$build/ti_ccd" "$truth" "$build/glc-toi" >"$build/ti.tsv"
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

# glc.tsv: scene kind queries true ns fp fn filtered
# ti.tsv:  scene kind queries true ns median fp fn toi_zero max_itr_hit late below_max
awk -F'\t' '
  FNR == NR { g[$1 FS $2] = $0; next }
  /^#/ { next }
  {
    k = $1 FS $2
    if (!(k in g)) { print "bench-ccd-peers: no glcollide row for " $1 " " $2 > "/dev/stderr"; bad = 1; next }
    split(g[k], a, FS)
    # The two sides must have read the same queries.
    if (a[3] != $3 || a[4] != $4) { print "bench-ccd-peers: " $1 " " $2 ": the two sides read different queries" > "/dev/stderr"; bad = 1; next }
    if (!header++) {
      print "| scene | kind | queries | true | glcollide ns/query | decided by the float filter | TI ns/query | TI median ns (wall) | TI / glcollide | glcollide FP / FN | TI FP / FN | TI toi = 0 | TI toi after t* | TI toi below t*, max |"
      print "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    }
    printf "| %s | %s | %d | %d | %d | %d (%.1f%%) | %d | %d | %.0fx | %d / %d | %d / %d | %d | %s | %s |\n",
      $1, $2, $3, $4, a[5], a[8], 100 * a[8] / ($3 > 0 ? $3 : 1), $5, $6, $5 / (a[5] > 0 ? a[5] : 1),
      a[6], a[7], $7, $8, $9, $11, $12
    # The whole run: total time over total queries (the big sets weigh most).
    n += $3; t += $4; gt += a[5] * $3; tt += $5 * $3; gf += a[8]
    gfp += a[6]; gfn += a[7]; fp += $7; fn += $8; z += $9
  }
  END {
    if (n > 0)
      printf "| all | | %d | %d | %.0f | %d (%.1f%%) | %.0f | | %.0fx | %d / %d | %d / %d | %d | | |\n",
        n, t, gt / n, gf, 100 * gf / n, tt / n, tt / (gt > 0 ? gt : 1), gfp, gfn, fp, fn, z
    exit bad
  }
' "$build/glc.tsv" "$build/ti.tsv"
echo
echo "CPU ns per query (the thread's CPU time, best of 3 runs of the whole set, each >= 0.2 s);" \
  "TI: tolerance 1e-6, max_itr 1e6, ms 0, err computed, no_zero_toi false (queries stopped by" \
  "max_itr: $(awk -F'\t' '!/^#/ { n += $10 } END { print n + 0 }' "$build/ti.tsv"))." \
  "t*: the exact earliest contact, within 2^-20 above glcollide's toi. TI toi after t*: TI's toi" \
  "above glcollide's + 2^-20 (not the lower bound TI promises). TI toi below t*: the largest" \
  "glcollide toi - TI toi over the queries both call true."
echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //');" \
  "load $load_before before, $load_after after; git $(git rev-parse --short HEAD 2>/dev/null || echo '?')."
