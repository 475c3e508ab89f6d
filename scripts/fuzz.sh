#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (FUZZING.md), one after another, niced.
#   scripts/fuzz.sh --runs 1000000 [TARGET...]   # each target for that many executions
#   scripts/fuzz.sh --seconds 600 [TARGET...]    # each target for that long
#   scripts/fuzz.sh --runs 1000000 --seconds 600 # whichever comes first
# TARGET: structure obj off ply stl opendx values map (default: all). Builds ./build-fuzz (clang,
# -DSPHEREMAP_FUZZ=ON: libFuzzer + AddressSanitizer + UndefinedBehaviorSanitizer) first, unless
# SPHEREMAP_FUZZ_BUILD=0 (the programs are there and another build of build-fuzz is running).
# Everything it writes goes to $SPHEREMAP_FUZZ_OUT (default /tmp/spheremap-fuzz), outside the repository:
#   OUT/TARGET/corpus/   the inputs libFuzzer found interesting (fuzz/corpus/TARGET is read, never written)
#   OUT/TARGET/crashes/  each finding (crash-*, leak-*, timeout-*, oom-*): fix it, then copy it into
#                        fuzz/regressions/TARGET/ so that ctest's Fuzz.TARGET replays it forever
#   OUT/TARGET.log       libFuzzer's output; the last lines give cov/ft and the executions
# Exits 1 if any target had a finding. Prints one line per target for FUZZING.md.
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { echo "usage: scripts/fuzz.sh [--runs N] [--seconds S] [TARGET...]" >&2; exit 1; }
limit=()
while [[ $# -ge 2 && "$1" == --* ]]; do
  case "$1" in
    --runs) limit+=(-runs="$2") ;;
    --seconds) limit+=(-max_total_time="$2") ;;
    *) usage ;;
  esac
  shift 2
done
[[ ${#limit[@]} -gt 0 ]] || usage
all=(structure obj off ply stl opendx values map)
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=("${all[@]}")
# Longest input per target: enough for every feature of the format, short enough for fast runs (the map
# target also skips meshes beyond 64 vertices / 128 faces, fuzz/fuzz_map.cpp).
declare -A max_len=([structure]=4096 [obj]=2048 [off]=2048 [ply]=2048 [stl]=2048 [opendx]=2048 [values]=2048
                    [map]=1024)
out="${SPHEREMAP_FUZZ_OUT:-/tmp/spheremap-fuzz}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [[ ! -f build-fuzz/CMakeCache.txt ]]; then
  cmake -S . -B build-fuzz "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DCMAKE_CXX_COMPILER=clang++ -DSPHEREMAP_FUZZ=ON -DSPHEREMAP_BUILD_TESTS=OFF -DSPHEREMAP_BUILD_BENCHMARKS=OFF >/dev/null
fi
for t in "${targets[@]}"; do
  [[ -n "${max_len[$t]:-}" ]] || { echo "scripts/fuzz.sh: unknown target '$t' (${all[*]})" >&2; exit 1; }
done
[[ "${SPHEREMAP_FUZZ_BUILD:-1}" == 0 ]] || nice cmake --build build-fuzz -j 2 --target "${targets[@]/#/fuzz_}"
# The targets write each input to a file under TMPDIR: memory is faster than the disk.
[[ -n "${TMPDIR:-}" || ! -d /dev/shm ]] || export TMPDIR=/dev/shm
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
found=0
for t in "${targets[@]}"; do
  mkdir -p "$out/$t/corpus" "$out/$t/crashes"
  start=$(date +%s)
  set +e
  nice build-fuzz/fuzz/fuzz_"$t" "$out/$t/corpus" "fuzz/corpus/$t" "${limit[@]}" -max_len="${max_len[$t]}" \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$out/$t/crashes/" >"$out/$t.log" 2>&1
  rc=$?
  set -e
  seconds=$(( $(date +%s) - start ))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$t.log" | tail -1)
  cov=$(grep -E '^#[0-9]+' "$out/$t.log" | tail -1 | grep -oE 'cov: [0-9]+ ft: [0-9]+' || true)
  findings=$(find "$out/$t/crashes" -type f | wc -l)
  (( rc == 0 && findings == 0 )) || found=1
  echo "$t: ${runs:-?} executions in ${seconds} s, ${cov:-cov: ?}, exit $rc, findings: $findings ($out/$t/crashes)"
done
exit "$found"
