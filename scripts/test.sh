#!/usr/bin/env bash
# Every test: Rust unit and integration tests, then the C programs, then each check in
# scripts/test.d/ (in name order). Installs what it needs first.
set -euo pipefail
cd "$(dirname "$0")/.."
extra=()
for f in scripts/test.d/*.deps; do [ -e "$f" ] && extra+=($(cat "$f")); done
bash scripts/deps.sh "${extra[@]}"
echo "== lints: rustfmt, clippy (warnings are errors; missing_docs on the public API), rustdoc"
cargo fmt --check
cargo clippy --release --locked --all-targets -q -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --release --locked --no-deps -q
# House rules (README length, file sizes, src/ffi over the public API only, C names only in
# src/ffi, docs/API.md in step with the header).
echo "== house rules"
bash scripts/check-house.sh
echo "== cargo test"
log=$(mktemp)
# Library, integration tests, doc examples, and benchmarks built (benchmarks are run by their own smoke
# check, not here).
if ! { cargo test --release --locked --lib --tests && cargo test --release --locked --doc &&
  cargo bench --locked --no-run; } >"$log" 2>&1; then
  grep -vE '^test .* ok$' "$log" | tail -80
  exit 1
fi
grep -E '^(     Running|test result|skipped:)' "$log"
echo "== C examples"
cargo build --release --locked
make -s -C examples-c
examples-c/build/api_errors
examples-c/build/readme_example
examples-c/build/abi_v01 data
examples-c/build/continuous_step data
# README.md's first C block shows examples-c/readme_example.c (from its #include on): keep the
# two identical.
diff -u <(sed -n '/^#include <glcollide.h>/,$p' examples-c/readme_example.c) \
  <(awk '/^```c$/ { inside = 1; next } inside && /^```$/ { exit } inside' README.md) ||
  { echo "README.md's C example differs from examples-c/readme_example.c" >&2; exit 1; }
FRAMES=60 bash scripts/demo.sh | tail -3
for t in scripts/test.d/*.sh; do
  [ -e "$t" ] || continue
  echo "== $t"
  bash "$t"
done
echo "all tests passed"
