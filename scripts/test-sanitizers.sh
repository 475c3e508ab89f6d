#!/usr/bin/env bash
# The unit tests (the bad-input table among them) under AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer
# included): a second build into ./build-asan, then ctest on the label given (default: unit). Any report fails
# the run (-fno-sanitize-recover=all, halt_on_error). The viewer's browser test is left out (Chromium is not
# instrumented and only slower under ASan); the viewer page is still built and its node tests run.
# Run after scripts/test.sh (which installs the dependencies); .ci/run does.
#   scripts/test-sanitizers.sh            # label unit
#   scripts/test-sanitizers.sh 'unit|data'  # the data tests too (slow)
set -euo pipefail
cd "$(dirname "$0")/.."
label="${1:-unit}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"
# -O1 -g1: a third faster to build than -O2 -g, with line numbers in every report.
cmake -S . -B build-asan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DSPHEREMAP_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-asan -j "$(nproc)" --target spheremap_cli spheremap_tests
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=0:detect_leaks=1:detect_odr_violation=2:strict_string_checks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
cd build-asan
ctest --output-on-failure -j "$(nproc)" -L "$label" -E "ViewerBrowser|Install\."
