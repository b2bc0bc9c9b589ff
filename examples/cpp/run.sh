#!/usr/bin/env bash
# Builds the static C ABI library, compiles the C++ client against the
# committed header and runs it; fails on any compile warning, violation or error.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -p shadowfocus-c
out="${TMPDIR:-/tmp}/shadowfocus_client.$$"
trap 'rm -f "$out"' EXIT
# -ffp-contract=off: the clip checks evaluate the matrix product with
# separate multiplies and adds, as the library's own checks do (no FMA).
${CXX:-g++} -std=c++17 -O2 -Wall -Wextra -Werror -ffp-contract=off -I crates/c/include \
    examples/cpp/shadowfocus_client.cpp target/release/libshadowfocus.a -lpthread -ldl -lm -o "$out"
"$out"
