#!/usr/bin/env bash
# Writes glcollide's CMake package config into <LIBDIR>/cmake/glcollide/ from the templates
# beside this script, after the library, header and pkg-config file are installed there
# (scripts/install.sh runs it after `cargo cinstall`; packagers may run it on a DESTDIR).
#
#   cmake/write-package-config.sh LIBDIR INCLUDEDIR
#
# LIBDIR and INCLUDEDIR are the directories as they are on disk now (DESTDIR included).
# Only their relative position goes into the files, so the installed tree stays movable.
# Version and static link line come from LIBDIR/pkgconfig/glcollide.pc, the library file
# and its soname from LIBDIR itself.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -eq 2 ] || { echo "usage: $0 LIBDIR INCLUDEDIR" >&2; exit 2; }
libdir=$(cd "$1" && pwd)
includedir=$(cd "$2" && pwd)
pc="$libdir/pkgconfig/glcollide.pc"
[ -f "$pc" ] || { echo "write-package-config: $pc not found (run cargo cinstall first)" >&2; exit 1; }
[ -f "$includedir/glcollide/glcollide.h" ] || { echo "write-package-config: $includedir/glcollide/glcollide.h not found" >&2; exit 1; }
[ -f "$libdir/libglcollide.a" ] || { echo "write-package-config: $libdir/libglcollide.a not found" >&2; exit 1; }

version=$(sed -n 's/^Version: *//p' "$pc")
[[ "$version" =~ ^([0-9]+)\.([0-9]+)\.([0-9]+) ]] || { echo "write-package-config: bad Version '$version' in $pc" >&2; exit 1; }
major=${BASH_REMATCH[1]} minor=${BASH_REMATCH[2]}
static_libs=$(sed -n 's/^Libs.private: *//p' "$pc" | xargs | tr ' ' ';')

# The real shared object (libglcollide.so.X.Y.Z) behind the development symlink, and its soname.
[ -e "$libdir/libglcollide.so" ] || { echo "write-package-config: $libdir/libglcollide.so not found" >&2; exit 1; }
shared_file=$(basename "$(readlink -f "$libdir/libglcollide.so")")
soname=$(readelf -d "$libdir/$shared_file" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ -n "$soname" ] || { echo "write-package-config: $shared_file has no SONAME (not built by cargo-c?)" >&2; exit 1; }
abi=$(sed -n 's/^#define GLCOL_ABI_VERSION \([0-9]*\).*/\1/p' "$includedir/glcollide/glcollide.h")
[ -n "$abi" ] || { echo "write-package-config: no GLCOL_ABI_VERSION in the installed header" >&2; exit 1; }
rel=$(realpath -m --relative-to="$libdir" "$includedir")
sizeof_void_p=$(getconf LONG_BIT); sizeof_void_p=$((sizeof_void_p / 8))

out="$libdir/cmake/glcollide"
mkdir -p "$out"
fill() {
  sed -e "s|@VERSION@|$version|g" -e "s|@VERSION_MAJOR@|$major|g" -e "s|@VERSION_MINOR@|$minor|g" \
      -e "s|@LIBDIR_TO_INCLUDEDIR@|$rel|g" -e "s|@SHARED_FILE@|$shared_file|g" \
      -e "s|@SONAME@|$soname|g" -e "s|@STATIC_LIBS@|$static_libs|g" -e "s|@ABI_VERSION@|$abi|g" \
      -e "s|@SIZEOF_VOID_P@|$sizeof_void_p|g" "$1" > "$2"
  if grep -q '@[A-Z_]*@' "$2"; then
    echo "write-package-config: unfilled placeholder in $2" >&2; exit 1
  fi
}
fill "$here/glcollideConfig.cmake.in" "$out/glcollideConfig.cmake"
fill "$here/glcollideConfigVersion.cmake.in" "$out/glcollideConfigVersion.cmake"
echo "write-package-config: $out/glcollideConfig.cmake ($version, $shared_file, soname $soname)"
