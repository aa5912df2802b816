#!/usr/bin/env bash
# Builds gpu-tracer/kernels to SPIR-V with rust-gpu and writes the committed
# module gpu-tracer/shaders/kernels.spv.  `--check` compares instead of writing
# (exit 1 if the committed module is stale).
#
# Needs the toolchain pinned in shader-builder/rust-toolchain.toml
# (nightly-2026-08-15 with rust-src, rustc-dev, llvm-tools). The codegen
# backend takes ~15 minutes to build on 2 cores, so it is cached outside the
# clone in $SHADER_CACHE (default ~/.cache/bluenoise-seeds).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cache="${SHADER_CACHE:-$HOME/.cache/bluenoise-seeds}"
mkdir -p "$cache" "$here/shaders"
export SHADER_TARGET_DIR="$cache/kernels-target"
cd "$here/shader-builder"
CARGO_TARGET_DIR="$cache/shader-builder" cargo run --release --quiet -- \
    "$here/kernels" "$here/shaders/kernels.spv" "$@"
