#!/usr/bin/env bash
# Builds glcollide with cargo-c and installs it like a distribution library:
#
#   bash scripts/install.sh [PREFIX]        # PREFIX defaults to /usr/local
#
# PREFIX/include/glcollide/glcollide.h             the header (the checked-in include/glcollide.h)
# PREFIX/LIBDIR/libglcollide.so.X.Y.Z              the shared library, soname libglcollide.so.0.MINOR
#               libglcollide.so.0.MINOR, .so       its soname and development symlinks
#               libglcollide.a                     the static library
#               pkgconfig/glcollide.pc             for pkg-config
#               cmake/glcollide/glcollideConfig{,Version}.cmake   for find_package(glcollide)
# PREFIX/lib/debug/.build-id/xx/yyyy.debug         the shared library's debug info (split off:
#                                                   the installed libraries are stripped)
#
# Environment: KEEP_DEBUG=1 (install the libraries unstripped), LIBDIR (relative to PREFIX,
# default lib; e.g. lib/x86_64-linux-gnu),
# DESTDIR (stage into DESTDIR/PREFIX, for packaging), CARGO_TARGET_DIR as for cargo.
# Installs cargo-c (cargo install --debug, 3 to 5 minutes on 2 cores; CARGO_C_RELEASE=1 builds
# it optimised, about 10) and the Debian packages its build needs only when they are missing.
# Without write access to PREFIX, the files are staged and copied with sudo.
#
# Without this script (cargo-c already installed): `cargo cinstall --release --prefix=PREFIX`
# installs everything but the CMake files, which `cmake/write-package-config.sh PREFIX/lib
# PREFIX/include` then writes (from cmake/*.cmake.in; every path in them is relative to the
# file, so the installed tree may be moved). `cargo cbuild` builds the same files into
# target/x86_64-unknown-linux-gnu/release/ without installing.
#
# Consumers (docs/INSTALL.md "Link"): pkg-config's Cflags (-I<prefix>/include/glcollide) and the
# CMake targets make `#include <glcollide.h>` work from any prefix; the CMake targets also add
# <prefix>/include, so <glcollide/glcollide.h> works there too (and with pkg-config when the
# prefix is /usr or /usr/local). glcollide::glcollide is the shared library (CMake puts its
# directory in the build tree's RPATH); glcollide::glcollide_static is libglcollide.a plus the
# system libraries Rust's standard library needs (`pkg-config --static --libs glcollide`).
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=${1:-/usr/local}
[[ "$prefix" = /* ]] || prefix="$(pwd)/$prefix"
libdir=${LIBDIR:-lib}
destdir=${DESTDIR:-}

CARGO_C_VERSION="0.10.24+cargo-0.98.0"
export PATH="${CARGO_HOME:-$HOME/.cargo}/bin:$PATH"

# cargo-c: the version pinned above unless a new enough one is already installed
# (Debian's cargo-c 0.9.x cannot read this crate's Cargo.lock).
have_cargo_c() {
  command -v cargo-cinstall >/dev/null || return 1
  local v
  v=$(cargo cinstall --version 2>/dev/null | awk '{print $2}')
  [[ "$v" =~ ^0\.([0-9]+)\.([0-9]+) ]] || return 1
  ((BASH_REMATCH[1] > 10 || (BASH_REMATCH[1] == 10 && BASH_REMATCH[2] >= 24)))
}
if ! have_cargo_c; then
  # openssl-sys needs pkg-config and the OpenSSL headers to build cargo's HTTP stack.
  bash scripts/deps.sh libssl-dev
  # Unoptimised (`--debug`, no debug info) unless CARGO_C_RELEASE=1: cargo-c only drives
  # cargo, and on 2 cores this builds in about 3 minutes instead of 10.
  profile=(--debug); [ "${CARGO_C_RELEASE:-0}" = 1 ] && profile=()
  echo "install: cargo install cargo-c $CARGO_C_VERSION ${profile[*]} (once; 3 to 10 minutes)"
  start=$SECONDS
  CARGO_PROFILE_DEV_DEBUG=0 cargo install cargo-c --version "$CARGO_C_VERSION" --locked --quiet "${profile[@]}"
  echo "install: cargo-c built in $((SECONDS - start)) s"
fi

stage=""
if [ -z "$destdir" ] && [ "$(id -u)" -ne 0 ]; then
  probe=$prefix
  while [ ! -e "$probe" ]; do probe=$(dirname "$probe"); done
  [ -w "$probe" ] || stage=$(mktemp -d)
fi

cargo cinstall --release --locked --prefix "$prefix" --libdir "$libdir" --includedir include \
  ${destdir:+--destdir "$destdir"} ${stage:+--destdir "$stage"}

root=${destdir:-${stage:-}}
bash cmake/write-package-config.sh "$root$prefix/$libdir" "$root$prefix/include"

# Ship lean, as distributions do: the shared library without debug info (symbols not needed
# for linking dropped too), its debug info in a separate file found by build id
# (PREFIX/lib/debug/.build-id/xx/yyyy.debug, the place gdb looks under /usr; for another
# prefix, `set debug-file-directory PREFIX/lib/debug`) and named by a .gnu_debuglink; the
# static library without debug info. KEEP_DEBUG=1 installs them as built.
if [ "${KEEP_DEBUG:-0}" != 1 ]; then
  lib="$root$prefix/$libdir"
  so=$(find "$lib" -maxdepth 1 -type f -name 'libglcollide.so.*' | head -1)
  id=$(readelf -n "$so" | sed -n 's/.*Build ID: *\([0-9a-f]*\).*/\1/p')
  if [ -n "$id" ]; then
    dbg="$root$prefix/lib/debug/.build-id/${id:0:2}/${id:2}.debug"
  else
    dbg="$lib/.debug/$(basename "$so").debug"
  fi
  mkdir -p "$(dirname "$dbg")"
  objcopy --only-keep-debug --compress-debug-sections=zlib "$so" "$dbg"
  chmod 0644 "$dbg"
  strip --strip-unneeded --remove-section=.comment "$so"
  objcopy --add-gnu-debuglink="$dbg" "$so"
  strip --strip-debug "$lib/libglcollide.a"
  echo "install: stripped $(basename "$so") ($(du -k "$so" | cut -f1) KiB; debug info $(du -k "$dbg" | cut -f1) KiB in ${dbg#"$root"}) and libglcollide.a ($(du -k "$lib/libglcollide.a" | cut -f1) KiB)"
fi

if [ -n "$stage" ]; then
  echo "install: copying into $prefix with sudo"
  sudo cp -a "$stage$prefix/." "$prefix/"
  rm -rf "$stage"
fi
# Refresh the loader cache for system prefixes so programs find the new soname.
if [ -z "$destdir" ] && command -v ldconfig >/dev/null &&
   { [ "$prefix" = /usr/local ] || [ "$prefix" = /usr ]; }; then
  if [ "$(id -u)" -eq 0 ]; then ldconfig; elif [ -n "$stage" ]; then sudo ldconfig; fi
fi
echo "install: glcollide installed into $destdir$prefix (libdir $libdir)"
