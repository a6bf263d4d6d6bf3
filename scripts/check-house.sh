#!/usr/bin/env bash
# House rules (issue 26) that a command can check. Each rule prints "ok" or "FAIL" with what
# breaks it; the exit status is 1 if any rule fails. Run from anywhere:
#   bash scripts/check-house.sh
# 1. README.md is at most 250 lines (a user's five-minute read).
# 2. No file under src/ is longer than 1,500 lines, its unit tests included.
# 3. src/ffi/ uses only the crate's public root API (what src/lib.rs makes public).
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

# 3. Every `crate::X` path in src/ffi/ (written out, or in a grouped import, also across
# lines) names an item the crate root re-exports (`pub use` in src/lib.rs; not a module, not
# even a public one), or one of the two one-list macros the root re-exports for the C
# layer's tables.
public=$(perl -0777 -ne '
  while (/^pub use [\w:]*::(?:\{([^}]*)\}|(\w+)(?: as (\w+))?)/mg) {
    if (defined $1) { for (split /,/, $1) { s/.*\bas\s+//; s/\s//g; print "$_\n" if length } }
    elsif (defined $3) { print "$3\n" } else { print "$2\n" }
  }' src/lib.rs | sort -u | tr '\n' ' ')
# (`ffi`: the C layer's own modules.)
allowed=" $public with_backends with_error_kinds ffi "
uses=$(find src/ffi -name '*.rs' | sort | while read -r f; do
  perl -0777 -ne '
    while (/crate::(\w+)/g) { print "$ARGV $1\n" }
    while (/crate::\{([^}]*)\}/gs) { my $g = $1; $g =~ s/\s+as\s+\w+//g; while ($g =~ /(?<![\w:])(\w+)/g) { print "$ARGV $1\n" } }
  ' "$f"
done | sort -u | while read -r f name; do
  case "$allowed" in *" $name "*) ;; *) echo "       $f: crate::$name" ;; esac
done)
if [ -z "$uses" ]; then
  ok "src/ffi/ uses only the crate root's public API (${public% })"
else
  bad "src/ffi/ reaches past the crate root's public API:"; echo "$uses"
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
