#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer included; -fno-sanitize-recover=all, -O1 -g1)
# in a second build, ./build-asan. Any report fails the run: the sanitizers exit 86 and the tests also look
# for their reports in every output.
#   scripts/test-sanitizers.sh        # CI (.ci/run, after scripts/test.sh): the command built with the
#                                     # sanitizers, run on every case of the bad-input table by the tests
#                                     # of ./build (SPHEREMAP_CLI); builds the library and the command only
#   scripts/test-sanitizers.sh --all  # every unit test built and run under the sanitizers (the command
#                                     # too): about twice the build time; the viewer's browser test and
#                                     # the install test left out
#   scripts/test-sanitizers.sh --all 'unit|data'   # the data tests too (slow)
set -euo pipefail
cd "$(dirname "$0")/.."
all=0
if [[ "${1:-}" == "--all" ]]; then all=1; shift; fi
label="${1:-unit}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"
cmake -S . -B build-asan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DSPHEREMAP_BUILD_BENCHMARKS=OFF >/dev/null
export ASAN_OPTIONS="exitcode=86:halt_on_error=1:detect_leaks=1:detect_odr_violation=2:strict_string_checks=1"
export UBSAN_OPTIONS="exitcode=86:halt_on_error=1:print_stacktrace=1"
# fontconfig's caches (pictures' text through cairo) live until exit: scripts/lsan-suppressions.txt.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt:print_suppressions=0"
if (( all )); then
  cmake --build build-asan -j "$(nproc)" --target spheremap_cli spheremap_tests
  cd build-asan
  ctest --output-on-failure -j "$(nproc)" -L "$label" -E "ViewerBrowser|Install\."
else
  cmake --build build-asan -j "$(nproc)" --target spheremap_cli
  [[ -x build/spheremap_tests ]] || { echo "test-sanitizers.sh: run scripts/test.sh first (it builds ./build)" >&2; exit 1; }
  export SPHEREMAP_CLI="$PWD/build-asan/spheremap"
  cd build
  ctest --output-on-failure -j "$(nproc)" -R "BadInput"
fi
