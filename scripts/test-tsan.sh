#!/usr/bin/env bash
# ThreadSanitizer on the maps made from several threads at once (docs/library.md, "Thread safety"): the
# library built with -fsanitize=thread into ./build-tsan, tests/sphere/threads_test.cpp compiled against it
# (LongThreads: 3 meshes x 4 threads x 50 rounds; DataThreads: a structure's whole job, if ../shared/data is
# there). Any report fails the run (exit 66). About 5 minutes in all on 2 cores (2026-11-28).
# OpenBLAS, CHOLMOD/UMFPACK and libgomp are not instrumented: TSan sees races in spheremap's own code only
# (the OpenBLAS race behind SolverSection was found with helgrind and a shim: CONTRIBUTING.md, "Threads").
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B build-tsan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DCMAKE_CXX_FLAGS=-fsanitize=thread -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread \
  -DSPHEREMAP_BUILD_TESTS=OFF -DSPHEREMAP_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-tsan -j "$(nproc)" --target spheremap_cli  # the library (and the command)
g++ -std=c++20 -fsanitize=thread -O1 -g1 -DGTEST_HAS_PTHREAD=1 -DFMT_SHARED \
  -DSPHEREMAP_SHARED_DATA_DIR="\"$PWD/../shared/data\"" -Iinclude -isystem /usr/include/eigen3 \
  tests/sphere/threads_test.cpp -o build-tsan/threads_tsan build-tsan/libspheremap.a -lgtest -lgtest_main -lfmt \
  -lcholmod -lumfpack -lamd -lcolamd -lcamd -lccolamd -lsuitesparseconfig -lgomp -lz -lpthread
TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1" ./build-tsan/threads_tsan
