#!/bin/sh
# Regenerates include/ccss.h from ffi/src with cbindgen 0.29.4.
#
#   ffi/gen_header.sh           rewrite include/ccss.h
#   ffi/gen_header.sh --check   fail (exit 1) if include/ccss.h is out of date
#
# CBINDGEN may name the cbindgen binary (default: cbindgen on PATH, else
# ~/.cargo/bin/cbindgen). Install it with: cargo install cbindgen --version 0.29.4 --locked
set -eu

want=0.29.4
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

if [ -z "${CBINDGEN:-}" ]; then
    if command -v cbindgen >/dev/null 2>&1; then
        CBINDGEN=cbindgen
    else
        CBINDGEN="$HOME/.cargo/bin/cbindgen"
    fi
fi
have=$("$CBINDGEN" --version 2>/dev/null | awk '{print $2}') || have=
if [ "$have" != "$want" ]; then
    echo "gen_header.sh: need cbindgen $want, found '${have:-none}' ($CBINDGEN)" >&2
    exit 2
fi

case "${1:-}" in
    "")
        "$CBINDGEN" --quiet --config ffi/cbindgen.toml --crate ccss-ffi --output include/ccss.h
        echo "wrote include/ccss.h"
        ;;
    --check)
        # Not `cbindgen --verify`: 0.29.4 rewrites the output file even then.
        # Generate a fresh copy elsewhere and compare.
        tmp=$(mktemp "${TMPDIR:-/tmp}/ccss.h.XXXXXX")
        trap 'rm -f "$tmp"' EXIT
        "$CBINDGEN" --quiet --config ffi/cbindgen.toml --crate ccss-ffi --output "$tmp"
        if diff -u include/ccss.h "$tmp"; then
            echo "include/ccss.h is up to date"
        else
            echo "include/ccss.h is out of date: run ffi/gen_header.sh" >&2
            exit 1
        fi
        ;;
    *)
        echo "usage: $0 [--check]" >&2
        exit 2
        ;;
esac
