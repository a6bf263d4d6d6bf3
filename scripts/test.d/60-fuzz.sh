#!/usr/bin/env bash
# Issue 6: runs each cargo-fuzz target for a bounded time (FUZZ_SECONDS each, default 25:
# about a minute in all), starting from fuzz/seeds/ and fuzz/regressions/. Longer locally:
#   FUZZ_SECONDS=600 bash scripts/test.d/60-fuzz.sh
# Only the stable toolchain exists here: RUSTC_BOOTSTRAP=1 lets it take the -Z flags
# cargo fuzz passes (sanitizer, coverage). cargo-fuzz is installed only if missing.
# A crash leaves its input in fuzz/artifacts/<target>/: fix the bug, then copy the input to
# fuzz/regressions/<target>/ (tests/ffi_fuzz_regressions.rs replays it in every cargo test).
set -euo pipefail
cd "$(dirname "$0")/../../fuzz"
secs=${FUZZ_SECONDS:-25}
export RUSTC_BOOTSTRAP=1
if ! cargo fuzz --version >/dev/null 2>&1; then
  echo "fuzz: installing cargo-fuzz"
  cargo install cargo-fuzz --locked --version 0.13.2 --quiet
fi
cargo fuzz build -O >/dev/null 2>&1 || cargo fuzz build -O
for t in scene_ops obj_parse; do
  corpus=$(mktemp -d)
  log=$(mktemp)
  if ! cargo fuzz run -O "$t" "$corpus" "seeds/$t" "regressions/$t" -- \
      -max_total_time="$secs" -print_final_stats=1 >"$log" 2>&1; then
    grep -vE '^#[0-9]+' "$log" | tail -60
    echo "fuzz: $t failed; its input is in fuzz/artifacts/$t/" >&2
    exit 1
  fi
  echo "fuzz: $t: $(grep -oE 'Done [0-9]+ runs in [0-9]+ second' "$log")s, no crash"
  rm -rf "$corpus" "$log"
done
