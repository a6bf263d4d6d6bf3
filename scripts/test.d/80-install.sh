#!/usr/bin/env bash
# Consumer test (issue 7): installs glcollide with scripts/install.sh (cargo-c) into a
# temporary prefix, then builds and runs, against that prefix only,
#   - a C program with `pkg-config --cflags --libs glcollide`,
#   - the same C program linked statically (`pkg-config --static`),
#   - the link lines of README.md and docs/INSTALL.md as written (prefix substituted),
#   - a C++ program with CMake `find_package(glcollide 0.1 REQUIRED)`, shared and static,
# and checks what they print against examples-c/consumer/expected.txt (two crossing squares,
# 3 contacts, derived by hand in examples-c/consumer/scene.h). Also checks the installed
# layout, the soname, the installed header (== include/glcollide.h) and the exported symbols.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
start=$SECONDS
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
consumer="$root/examples-c/consumer"

# cargo-c builds into <target dir>/<host triple>/release (an explicit target, with a soname),
# so it does not disturb target/release; build scripts and proc macros are shared.
log="$work/install.log"
if ! bash scripts/install.sh "$prefix" >"$log" 2>&1; then
  tail -40 "$log"; echo "FAIL scripts/install.sh"; exit 1
fi
grep -E '^install: cargo-c built' "$log" || true
echo "install: $((SECONDS - start)) s"

fail=0
ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; fail=1; }

# Layout.
version=$(sed -n 's/^version *= *"\(.*\)"/\1/p' Cargo.toml | head -1)
IFS=. read -r major minor patch <<<"$version"
if [ "$major" = 0 ]; then sover="0.$minor"; else sover="$major"; fi
for f in include/glcollide/glcollide.h "lib/libglcollide.so.$version" "lib/libglcollide.so.$sover" \
         lib/libglcollide.so lib/libglcollide.a lib/pkgconfig/glcollide.pc \
         lib/cmake/glcollide/glcollideConfig.cmake lib/cmake/glcollide/glcollideConfigVersion.cmake; do
  [ -e "$prefix/$f" ] && ok "installed $f" || bad "missing $f"
done
cmp -s include/glcollide.h "$prefix/include/glcollide/glcollide.h" \
  && ok "installed header is include/glcollide.h" || bad "installed header differs from include/glcollide.h"
soname=$(readelf -d "$prefix/lib/libglcollide.so.$version" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ "$soname" = "libglcollide.so.$sover" ] && ok "soname $soname" || bad "soname '$soname', want libglcollide.so.$sover"

# Shipped lean (issue 14): no debug info in the installed libraries; the shared library's
# is split off under lib/debug/.build-id and gdb finds it there (file and line of a symbol).
so="$prefix/lib/libglcollide.so.$version"
if readelf -S "$so" | grep -q '\.debug_info'; then bad "installed $(basename "$so") has debug info"; fi
if readelf -S "$prefix/lib/libglcollide.a" | grep -q '\.debug_info'; then bad "installed libglcollide.a has debug info"; fi
id=$(readelf -n "$so" | sed -n 's/.*Build ID: *\([0-9a-f]*\).*/\1/p')
dbg="$prefix/lib/debug/.build-id/${id:0:2}/${id:2}.debug"
if [ -n "$id" ] && readelf -S "$dbg" 2>/dev/null | grep -q '\.debug_info'; then
  ok "debug info split off into lib/debug/.build-id/${id:0:2}/${id:2}.debug"
else
  bad "no debug file for build id '$id'"
fi
line=$(gdb -nx -batch -iex "set debug-file-directory $prefix/lib/debug" -ex "info line glcol_query_all" "$so" 2>&1 | grep -m1 -o 'Line [0-9]* of "[^"]*"' || true)
[[ "$line" == *src/ffi/query.rs* ]] && ok "gdb finds glcol_query_all at $line through the split debug info" \
  || bad "gdb does not find glcol_query_all's source line: '$line'"
size_of() { du -k "$1" | cut -f1; }
ok "sizes: $(basename "$so") $(size_of "$so") KiB, its debug info $(size_of "$dbg") KiB, libglcollide.a $(size_of "$prefix/lib/libglcollide.a") KiB"

# Exported symbols of the installed library == the header's functions.
# Declarations start in column 0 (comments start with // or " *").
header_fns=$(grep -E '^[A-Za-z]' include/glcollide.h | grep -oE '\bglcol_[a-z0-9_]+\(' | tr -d '(' | sort -u)
exported=$(nm -D --defined-only "$prefix/lib/libglcollide.so.$version" | awk '{print $3}' | sort -u)
if [ "$header_fns" = "$exported" ]; then
  ok "exports = the header's $(wc -l <<<"$exported") functions"
else
  bad "exports differ from the header's functions:"; diff <(echo "$header_fns") <(echo "$exported") | sed 's/^/     /' || true
fi

export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
pcv=$(pkg-config --modversion glcollide)
[ "$pcv" = "$version" ] && ok "pkg-config --modversion glcollide = $pcv" || bad "pkg-config version '$pcv', want $version"

check_run() { # name, program...
  local name=$1; shift
  local out
  if ! out=$("$@" 2>"$work/$name.err"); then
    bad "$name exited non-zero: $(cat "$work/$name.err")"; return
  fi
  if [ "$out" = "$(cat "$consumer/expected.txt")" ]; then
    ok "$name: $(head -1 <<<"$out") ($(tr -d '\n' <"$work/$name.err"))"
  else
    bad "$name printed:"; sed 's/^/     /' <<<"$out"; echo "     expected:"; sed 's/^/     /' "$consumer/expected.txt"
  fi
}

# C through pkg-config: shared (rpath to the prefix's libdir: not a system prefix) ...
cflags=(-std=c11 -Wall -Wextra -Wpedantic -Werror)
libdir=$(pkg-config --variable=libdir glcollide)
# shellcheck disable=SC2046
if cc "${cflags[@]}" "$consumer/consumer.c" $(pkg-config --cflags --libs glcollide) \
     -Wl,-rpath,"$libdir" -o "$work/consumer_c"; then
  # ldd's output is kept first: `ldd | grep -q` under pipefail fails when grep exits before
  # ldd has written everything (SIGPIPE), a flake seen in CI.
  ldd "$work/consumer_c" >"$work/consumer_c.ldd"
  grep -q "libglcollide.so.$sover => $libdir/" "$work/consumer_c.ldd" \
    && ok "consumer_c loads $libdir/libglcollide.so.$sover" || bad "consumer_c does not load the installed soname: $(grep glcollide "$work/consumer_c.ldd")"
  check_run consumer_c "$work/consumer_c"
else
  bad "consumer.c does not build with pkg-config --cflags --libs glcollide"
fi
# ... and static (the .a plus pkg-config's Libs.private).
# shellcheck disable=SC2046
if cc "${cflags[@]}" "$consumer/consumer.c" $(pkg-config --cflags glcollide) "$libdir/libglcollide.a" \
     $(pkg-config --static --libs-only-l glcollide | sed 's/-lglcollide//') -o "$work/consumer_c_static"; then
  ldd "$work/consumer_c_static" >"$work/consumer_c_static.ldd"
  grep -q glcollide "$work/consumer_c_static.ldd" && bad "consumer_c_static links libglcollide.so" || true
  check_run consumer_c_static "$work/consumer_c_static"
else
  bad "consumer.c does not link statically with pkg-config --static"
fi

# The link lines a reader copies (issue 26: a README line that only worked under /usr): every
# ```sh block of README.md and docs/INSTALL.md that links `app.c`, run as written in a fresh
# directory with the consumer as app.c, the install command left out and $HOME/.local
# replaced by this prefix, without our PKG_CONFIG_PATH. Each program it makes (-o NAME) must
# print the expected answer; one linked with --static must not load libglcollide.so.
link_blocks() { # file
  awk '/^```sh$/ { inb = 1; b = ""; next }
       inb && /^```$/ { inb = 0; if (b ~ /cc app\.c/) printf "%s", b; next }
       inb { b = b $0 "\n" }' "$1"
}
for doc in README.md docs/INSTALL.md; do
  lines=$(link_blocks "$doc" | grep -v 'scripts/install\.sh' || true)
  if [ -z "$lines" ]; then bad "$doc: no \`\`\`sh block links app.c"; continue; fi
  lines=${lines//'$HOME/.local'/$prefix}
  d="$work/doc-$(basename "$doc" .md)"
  mkdir -p "$d"
  cp "$consumer/consumer.c" "$d/app.c"
  cp "$consumer"/*.h "$d/"
  if ! (cd "$d" && env -u PKG_CONFIG_PATH bash -euo pipefail -c "$lines") >"$d/log" 2>&1; then
    bad "$doc: its link lines fail against a prefix outside /usr:"; sed 's/^/     /' "$d/log"
    continue
  fi
  # One command per line (continuations joined), then the program each one writes.
  joined=$(sed -e ':a' -e '/\\$/N; s/\\\n//; ta' <<<"$lines")
  made=0
  while read -r cmd; do
    prog=$(grep -oE -- '-o [A-Za-z0-9_]+' <<<"$cmd" | cut -d' ' -f2)
    [ -n "$prog" ] || continue
    made=$((made + 1))
    check_run "$(basename "$doc") $prog" "$d/$prog"
    if [[ "$cmd" == *--static* ]]; then
      ldd "$d/$prog" >"$d/$prog.ldd"
      if grep -q glcollide "$d/$prog.ldd"; then bad "$doc: $prog (static) loads libglcollide.so"; fi
    fi
  done < <(grep -E '^cc ' <<<"$joined")
  [ "$made" -ge 2 ] || bad "$doc: expected a shared and a static link line, found $made programs"
done

# C++ through CMake find_package, shared and static; the prefix is found only through
# CMAKE_PREFIX_PATH (no pkg-config involved).
for kind in shared static; do
  b="$work/cmake-$kind"
  static=OFF; [ $kind = static ] && static=ON
  if env -u PKG_CONFIG_PATH cmake -S "$consumer" -B "$b" -DCMAKE_PREFIX_PATH="$prefix" \
       -DGLCOLLIDE_STATIC=$static -DCMAKE_BUILD_TYPE=Release >"$work/cmake-$kind.log" 2>&1 &&
     cmake --build "$b" >>"$work/cmake-$kind.log" 2>&1; then
    check_run "consumer_cpp ($kind)" "$b/consumer_cpp"
  else
    tail -30 "$work/cmake-$kind.log"; bad "consumer.cpp does not build with find_package(glcollide) ($kind)"
  fi
done
# The version file: same soname series and not older than asked.
mkdir -p "$work/ver"
cat >"$work/ver/CMakeLists.txt" <<CM
cmake_minimum_required(VERSION 3.19)
project(glcollide_version_checks LANGUAGES NONE)
foreach(v IN ITEMS 0.$((minor + 1)) $major.$minor.$((patch + 1)) $major.$minor.$((patch + 1))...$major.$minor.$((patch + 9)) $((major + 1)))
  find_package(glcollide \${v} QUIET)
  if(glcollide_FOUND)
    message(FATAL_ERROR "find_package(glcollide \${v}) accepted \${glcollide_VERSION}")
  endif()
endforeach()
foreach(v IN ITEMS $major.$minor $version 0.$minor...<0.$((minor + 1)) 0.$minor...0.$((minor + 5)))
  unset(glcollide_DIR CACHE)
  find_package(glcollide \${v} REQUIRED)
endforeach()
find_package(glcollide $version EXACT REQUIRED)
if(NOT glcollide_VERSION STREQUAL "$version" OR NOT glcollide_ABI_VERSION GREATER 0)
  message(FATAL_ERROR "glcollide_VERSION \${glcollide_VERSION}, ABI \${glcollide_ABI_VERSION}")
endif()
CM
if cmake -S "$work/ver" -B "$work/ver/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/ver.log" 2>&1; then
  ok "find_package(glcollide) version rules"
else
  tail -20 "$work/ver.log"; bad "find_package(glcollide) version rules"
fi

# A moved prefix still works (the CMake config is relocatable).
mv "$prefix" "$work/moved"
if cmake -S "$consumer" -B "$work/cmake-moved" -DCMAKE_PREFIX_PATH="$work/moved" >/dev/null 2>&1 &&
   cmake --build "$work/cmake-moved" >/dev/null 2>&1; then
  check_run "consumer_cpp (moved prefix)" "$work/cmake-moved/consumer_cpp"
else
  bad "find_package in a moved prefix"
fi

echo "80-install: $((SECONDS - start)) s"
if [ $fail -ne 0 ]; then echo "80-install: FAILED"; exit 1; fi
echo "80-install: all consumer checks passed"
