#!/usr/bin/env bash
# The main job: builds glcollide and runs the C demo (a blade in a deforming gallbladder,
# headless) on the meshes bundled in data/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cargo build --release --locked
make -s -C examples-c
examples-c/build/deform_demo data "${FRAMES:-300}" "${EPSILON:-0}"
# Continuous detection: a blade through a membrane between two clean frames.
examples-c/build/continuous_step data
