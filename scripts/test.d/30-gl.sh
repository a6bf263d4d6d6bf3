#!/usr/bin/env bash
# The GL host example: its own headless EGL context (Mesa llvmpipe, no GPU or display
# needed), glcollide called between its draws on all three backends; fails if the host's
# GL state changed, if the backends disagree, or if no PNG was written.
set -euo pipefail
cd "$(dirname "$0")/../.."
make -s -C examples-c
out=$(mktemp -d)/gl_host.png
examples-c/build/gl_host data "${FRAMES:-30}" "$out"
test -s "$out"
# The GL backends (GL_COMPUTE whole query, GL_SELECT) against the CPU on
# the demo scene and an organ pair, 3 frames: exits 1 if any contact differs.
cargo bench --locked -q --bench gl -- 3
