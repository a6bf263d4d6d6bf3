#!/usr/bin/env bash
# House rules (issue 26) that a command can check. Each rule prints "ok" or "FAIL" with what
# breaks it; the exit status is 1 if any rule fails. Run from anywhere:
#   bash scripts/check-house.sh
# 1. README.md is at most 250 lines (a user's five-minute read).
# 2. No file under src/ is longer than 1,500 lines, its unit tests included.
# 3. src/ffi/ uses only the crate's public root API: no path into crate::backend, mesh, gpu,
#    obj, geom, query, bvh or scene.
# 4. The C names (glcol_*, GLCOL_*) appear in src/ only under src/ffi/ (the core does not
#    know C).
# 5. docs/API.md and include/glcollide.h name the same things (cargo test --test docs).
set -uo pipefail
cd "$(dirname "$0")/.."
fail=0
ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; fail=1; }

# 1.
n=$(wc -l <README.md)
if [ "$n" -le 250 ]; then ok "README.md: $n lines (at most 250)"; else bad "README.md: $n lines, more than 250"; fi

# 2.
long=$(find src -name '*.rs' -exec wc -l {} + | awk '$2 != "total" && $1 > 1500 { print "       " $2 ": " $1 " lines" }')
if [ -z "$long" ]; then ok "no file under src/ above 1,500 lines"; else bad "files under src/ above 1,500 lines:"; echo "$long"; fi

# 3. Paths written out (crate::mesh::x) and grouped imports (use crate::{mesh::x, ...}), also
# across lines.
internals='backend|mesh|gpu|obj|geom|query|bvh|scene'
uses=$(find src/ffi -name '*.rs' | sort | while read -r f; do
  perl -0777 -ne '
    while (/crate::('"$internals"')\b/g) { print "$ARGV: crate::$1\n" }
    while (/crate::\{([^}]*)\}/gs) { my $g = $1; while ($g =~ /(?<![\w:])('"$internals"')\b/g) { print "$ARGV: crate::{.. $1 ..}\n" } }
  ' "$f"
done | sort | uniq -c | sed 's/^ *\([0-9]*\) \(.*\)/       \2 (x\1)/')
if [ -z "$uses" ]; then
  ok "src/ffi/ imports nothing from crate::{$internals}"
else
  bad "src/ffi/ reaches into the crate's internals (only the public root API is allowed):"; echo "$uses"
fi

# 4.
c_names=$(grep -rnE 'glcol_|GLCOL_' src --include='*.rs' | grep -v '^src/ffi/' | sed 's/^/       /')
if [ -z "$c_names" ]; then
  ok "glcol_/GLCOL_ appear in src/ only under src/ffi/"
else
  bad "glcol_/GLCOL_ outside src/ffi/ ($(wc -l <<<"$c_names") lines):"; echo "$c_names"
fi

# 5.
log=$(mktemp)
if cargo test --release --locked -q --test docs >"$log" 2>&1; then
  ok "docs/API.md names what include/glcollide.h declares, and only that (tests/docs.rs)"
else
  bad "docs/API.md and include/glcollide.h are out of step (tests/docs.rs):"
  grep -E 'panicked|declares|does not' "$log" | sed 's/^/       /'
fi
rm -f "$log"

if [ "$fail" -ne 0 ]; then echo "check-house: FAILED"; exit 1; fi
echo "check-house: all rules hold"
