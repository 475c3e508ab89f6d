#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer included; -fno-sanitize-recover=all) in a
# second build, ./build-asan: the library and the command at -O1 -g1 (the core library compiled in unity
# batches of 16 sources: SPHEREMAP_UNITY_CORE), the test sources at -O0 -g1 (they take half the build; the
# code under test keeps -O1). Any report fails the run: the sanitizers exit 86 and
# the tests also look for their reports in every output.
#   scripts/test-sanitizers.sh                 # CI (.ci/run, after scripts/test.sh): every unit test,
#                                              # the bad-input table included (it runs the command built
#                                              # with the sanitizers); not the viewer's browser test (the
#                                              # page runs in Chromium) nor the install test
#   scripts/test-sanitizers.sh 'unit|data'     # the data tests too (slow)
set -euo pipefail
cd "$(dirname "$0")/.."
label="${1:-unit}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"
cmake -S . -B build-asan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DSPHEREMAP_BUILD_BENCHMARKS=OFF \
  -DSPHEREMAP_TEST_COMPILE_OPTIONS="-O0" -DSPHEREMAP_UNITY_CORE=ON >/dev/null
export ASAN_OPTIONS="exitcode=86:halt_on_error=1:detect_leaks=1:detect_odr_violation=2:strict_string_checks=1"
export UBSAN_OPTIONS="exitcode=86:halt_on_error=1:print_stacktrace=1"
# fontconfig's caches (pictures' text through cairo) live until exit: scripts/lsan-suppressions.txt.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt:print_suppressions=0"
cmake --build build-asan -j "$(nproc)" --target spheremap_cli spheremap_tests
cd build-asan
# A test that hangs fails after 10 minutes instead of using up CI's time (the slowest takes about 1.5 min).
ctest --output-on-failure -j "$(nproc)" -L "$label" -E "ViewerBrowser|Install\." --timeout 600
