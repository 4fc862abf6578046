#!/usr/bin/env bash
# Builds and installs the ccss C library for C/C++ hosts.
#
#   scripts/install.sh [--prefix DIR] [options]      build (release) and install
#   scripts/install.sh --uninstall [--prefix DIR]    remove what an install put there
#
# Installs, under PREFIX (default /usr/local):
#   include/ccss.h
#   LIBDIR/libccss.a
#   LIBDIR/libccss.so.X.Y.Z  (soname libccss.so.SOVERSION, set by ffi/build.rs)
#   LIBDIR/libccss.so.SOVERSION -> libccss.so.X.Y.Z,  LIBDIR/libccss.so -> libccss.so.SOVERSION
#   LIBDIR/pkgconfig/ccss.pc, LIBDIR/pkgconfig/ccss-static.pc
#   LIBDIR/cmake/ccss/ccssConfig.cmake, ccssConfigVersion.cmake
#   share/ccss/install_manifest.txt   (the list --uninstall removes)
# SOVERSION is the major version, or 0.MINOR before 1.0 (0.2 for 0.2.x).
#
# Options
#   --prefix DIR       installation prefix (default /usr/local)
#   --libdir DIR       library directory, relative to the prefix or absolute
#                      inside it (default lib; e.g. lib/x86_64-linux-gnu)
#   --destdir DIR      stage into DIR/PREFIX/... (packaging; also $DESTDIR);
#                      the installed files still refer to PREFIX
#   --target-dir DIR   cargo target directory (default: cargo's own)
#   --build-only       build, do not install (then, e.g., sudo ... --no-build)
#   --no-build         install what an earlier build left in the target dir
#                      (runs no cargo; --target-dir if not target/)
#   --uninstall        remove the files listed in the prefix's manifest
#   -q, --quiet        print only errors
#
# Needs cargo (and its rustc) and coreutils; readelf (binutils), if present,
# is used to check the soname. CARGO may name the cargo binary.
#
# Why not cargo-c (`cargo cinstall`)? It does the same job but is not in
# Debian 12, and `cargo install cargo-c` (0.10.24, the newest release that
# builds with Rust 1.95) compiles 348 crates (cargo itself, gix, curl,
# openssl): 16 CPU-minutes, 13 minutes on the 2-core CI machine, for what is
# here 200 lines of shell. This script follows its conventions (soname,
# pkg-config Libs.private) and adds a CMake package, which cargo-c does not
# write. tests/tests/host_integration.rs tests it end to end.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
prefix=/usr/local
libdir=lib
destdir=${DESTDIR:-}
target_dir=
build=1
build_only=0
uninstall=0
quiet=0
cargo=${CARGO:-cargo}

die() { echo "install.sh: $*" >&2; exit 1; }
say() { [ "$quiet" = 1 ] || echo "$@"; }

while [ $# -gt 0 ]; do
    case "$1" in
        --prefix) prefix=${2:?--prefix needs a directory}; shift 2 ;;
        --prefix=*) prefix=${1#*=}; shift ;;
        --libdir) libdir=${2:?--libdir needs a directory}; shift 2 ;;
        --libdir=*) libdir=${1#*=}; shift ;;
        --destdir) destdir=${2:?--destdir needs a directory}; shift 2 ;;
        --destdir=*) destdir=${1#*=}; shift ;;
        --target-dir) target_dir=${2:?--target-dir needs a directory}; shift 2 ;;
        --target-dir=*) target_dir=${1#*=}; shift ;;
        --no-build) build=0; shift ;;
        --build-only) build_only=1; shift ;;
        --uninstall) uninstall=1; shift ;;
        -q|--quiet) quiet=1; shift ;;
        -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) die "unknown argument '$1' (see --help)" ;;
    esac
done

case "$prefix" in /*) ;; *) die "--prefix must be an absolute path (got '$prefix')" ;; esac
prefix=${prefix%/}
[ -n "$prefix" ] || prefix=/
case "$libdir" in
    /*) case "$libdir/" in
            "$prefix"/*) libdir=${libdir#"$prefix"/} ;;
            *) die "--libdir '$libdir' is not inside the prefix '$prefix'" ;;
        esac ;;
esac
libdir=${libdir%/}
case "/$libdir/" in */../*|*/./*|//) die "--libdir must be a plain relative path (got '$libdir')" ;; esac
includedir=include
stage=${destdir%/}$prefix
manifest_rel=share/ccss/install_manifest.txt

if [ "$uninstall" = 1 ]; then
    manifest=$stage/$manifest_rel
    [ -f "$manifest" ] || die "no ccss installation in $stage (missing $manifest)"
    while IFS= read -r rel; do
        [ -n "$rel" ] || continue
        rm -f "$stage/$rel"
        # Remove the directories the install created, if now empty.
        d=$(dirname "$stage/$rel")
        while [ "$d" != "$stage" ] && rmdir "$d" 2>/dev/null; do d=$(dirname "$d"); done
    done < "$manifest"
    rm -f "$manifest"
    rmdir "$stage/share/ccss" "$stage/share" 2>/dev/null || true
    say "install.sh: removed ccss from $stage"
    exit 0
fi

# 1. Build. `cargo rustc` (not `cargo build`) so that rustc reports the
# system libraries the static library needs; cargo replays that note when
# the build is already fresh. The build writes what the install step needs
# into the target directory, so that `--no-build` (e.g. under sudo, where
# cargo may not be on the PATH) runs no cargo at all.
cd "$root"
cargo_args=(--release -p ccss-ffi --lib)
[ -n "$target_dir" ] && cargo_args+=(--target-dir "$target_dir")
if [ -z "$target_dir" ]; then
    target_dir=${CARGO_TARGET_DIR:-}
fi
if [ -z "$target_dir" ]; then
    if [ "$build" = 1 ]; then
        target_dir=$("$cargo" metadata --format-version 1 --no-deps |
            sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
        [ -n "$target_dir" ] || die "cannot find cargo's target directory"
    else
        target_dir=$root/target
    fi
fi
case "$target_dir" in /*) ;; *) target_dir=$root/$target_dir ;; esac
out=$target_dir/release
notes=$target_dir/ccss-install-notes.txt
saved=$target_dir/ccss-install-version.txt
if [ "$build" = 1 ]; then
    say "install.sh: building ccss-ffi (release) in $target_dir"
    mkdir -p "$target_dir"
    if [ "$quiet" = 1 ]; then
        "$cargo" rustc --quiet "${cargo_args[@]}" -- --print native-static-libs > "$notes" 2>&1 ||
            { cat "$notes" >&2; die "cargo rustc failed"; }
    else
        "$cargo" rustc "${cargo_args[@]}" -- --print native-static-libs 2>&1 | tee "$notes" ||
            die "cargo rustc failed"
    fi
    "$cargo" pkgid -p ccss-ffi | sed 's/.*[@#]//' > "$saved"
fi
[ -f "$notes" ] && [ -f "$saved" ] || die "no build in $target_dir: run without --no-build first"
native_libs=$(sed -n 's/.*native-static-libs: *//p' "$notes" | tail -n 1)
[ -n "$native_libs" ] || die "rustc printed no native-static-libs note (see $notes)"
native_libs=$(echo $native_libs) # one line, single spaces
version=$(cat "$saved")
case "$version" in [0-9]*.[0-9]*.[0-9]*) ;; *) die "cannot read the version of ccss-ffi (got '$version')" ;; esac
major=${version%%.*}
rest=${version#*.}
minor=${rest%%.*}
if [ "$major" = 0 ]; then soversion=0.$minor; else soversion=$major; fi
soname=libccss.so.$soversion
real=libccss.so.$version

for f in "$out/libccss.a" "$out/libccss.so" "$root/include/ccss.h"; do
    [ -f "$f" ] || die "$f missing"
done
if command -v readelf >/dev/null 2>&1; then
    got=$(readelf -d "$out/libccss.so" | sed -n 's/.*Library soname: \[\(.*\)\].*/\1/p')
    [ "$got" = "$soname" ] || die "$out/libccss.so has soname '$got', expected '$soname' (ffi/build.rs)"
fi

if [ "$build_only" = 1 ]; then
    say "install.sh: built ccss $version; install with: $0 --no-build --prefix ..."
    exit 0
fi

# 2. Install.
installed=()
put() { # put MODE SRC REL: copy SRC to $stage/REL (timestamps kept)
    mkdir -p "$(dirname "$stage/$3")"
    rm -f "$stage/$3"
    install -p -m "$1" "$2" "$stage/$3"
    installed+=("$3")
}
link() { # link TARGET REL: symlink $stage/REL -> TARGET
    rm -f "$stage/$2"
    ln -s "$1" "$stage/$2"
    installed+=("$2")
}
# Templates: @NAME@ -> value (values escaped for sed).
esc() { printf '%s' "$1" | sed -e 's/[\\|&]/\\&/g'; }
render() { # render TEMPLATE REL
    local tmp
    tmp=$(mktemp)
    sed -e "s|@PREFIX@|$(esc "$prefix")|g" \
        -e "s|@LIBDIR@|\${prefix}/$(esc "$libdir")|g" \
        -e "s|@INCLUDEDIR@|\${prefix}/$includedir|g" \
        -e "s|@LIBDIR_REL@|$(esc "$libdir")|g" \
        -e "s|@INCLUDEDIR_REL@|$includedir|g" \
        -e "s|@CMAKEDIR_TO_PREFIX@|$cmake_up|g" \
        -e "s|@VERSION@|$version|g" \
        -e "s|@VERSION_MAJOR@|$major|g" \
        -e "s|@VERSION_MINOR@|$minor|g" \
        -e "s|@SONAME@|$soname|g" \
        -e "s|@SHARED_REAL@|$real|g" \
        -e "s|@NATIVE_STATIC_LIBS@|$(esc "$native_libs")|g" \
        -e "s|@NATIVE_STATIC_LIBS_CMAKE@|$(esc "${native_libs// /;}")|g" \
        -e "s|@SIZEOF_VOID_P@|8|g" \
        "$root/$1" > "$tmp"
    if grep -q '@[A-Z_]*@' "$tmp"; then
        rm -f "$tmp"
        die "unreplaced placeholder in $1"
    fi
    # Keep the old file (and its timestamp) when nothing changed.
    if [ -f "$stage/$2" ] && cmp -s "$tmp" "$stage/$2"; then
        rm -f "$tmp"
        installed+=("$2")
    else
        put 644 "$tmp" "$2"
        rm -f "$tmp"
    fi
}
# From LIBDIR/cmake/ccss back to the prefix: one ".." per path component.
cmake_up=..
IFS=/ read -r -a parts <<< "$libdir/cmake"
for _ in "${parts[@]}"; do cmake_up=$cmake_up/..; done

put 644 "$root/include/ccss.h" "$includedir/ccss.h"
put 644 "$out/libccss.a" "$libdir/libccss.a"
put 755 "$out/libccss.so" "$libdir/$real"
link "$real" "$libdir/$soname"
link "$soname" "$libdir/libccss.so"
render pkgconfig/ccss.pc.in "$libdir/pkgconfig/ccss.pc"
render pkgconfig/ccss-static.pc.in "$libdir/pkgconfig/ccss-static.pc"
render cmake/ccssConfig.cmake.in "$libdir/cmake/ccss/ccssConfig.cmake"
render cmake/ccssConfigVersion.cmake.in "$libdir/cmake/ccss/ccssConfigVersion.cmake"
mkdir -p "$stage/share/ccss"
printf '%s\n' "${installed[@]}" > "$stage/$manifest_rel"

say "install.sh: installed ccss $version into $stage"
for f in "${installed[@]}"; do say "  $f"; done
say "static link line: -I$prefix/$includedir $prefix/$libdir/libccss.a $native_libs"
