#!/usr/bin/env bash
# Configures and builds spheremap (Release) into ./build: the targets given as arguments (e.g.
# spheremap_cli: the library and the command only), or everything (tests and benchmarks included).
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
