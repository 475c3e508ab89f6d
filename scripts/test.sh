#!/usr/bin/env bash
# Command (2) of the README: install what is missing, build, and run every test (unit and data).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh  # everything: the tests, the benchmarks, the example
cd build
ctest --output-on-failure -j "$(nproc)" "$@"
