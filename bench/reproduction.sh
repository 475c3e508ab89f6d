#!/usr/bin/env bash
# The runs behind REPRODUCTION.md: the paper set under the paper's settings and under our defaults, each
# with the paper's genus filter (--keep-topology) and with our repair, three weightings, then Table 1 and
# Figure 4 for each run folder. Prints each batch's wall time.
#   bench/reproduction.sh [OUT]   (default OUT: runs/reproduction; existing complete runs are redone)
set -euo pipefail
cd "$(dirname "$0")/.."
P=../shared/data/pdb/paper77
[ -d "$P" ] || { echo "reproduction.sh: $P not found" >&2; exit 1; }
out=${1:-runs/reproduction}
bin=./build/spheremap
W=uniform,cotan,mean-value
run() {
  local name=$1; shift
  local start; start=$(date +%s.%N)
  "$bin" batch "$P" -o "$out/$name" --jobs 2 --weights $W --force -q --no-pictures "$@" > "$out/$name.log" 2>&1 || true
  printf '%-28s %6.1f s  %s\n' "$name" "$(echo "$(date +%s.%N) - $start" | bc)" "$(tail -1 "$out/$name.log")"
}
mkdir -p "$out"
run paper-filter --preset paper --keep-topology
run paper-repair --preset paper
run default-filter --keep-topology
run default-repair
# The paper's probe on a fine grid, simplified to the paper's triangle counts (about 2 Å edges): tests
# whether the uniform-weight distortion comes from uneven triangles (REPRODUCTION.md, difference 3).
run paper-simplified --preset paper --grid 0.5 --mesh-edge 2
for d in "$out"/*/; do "$bin" table "$d" > /dev/null; done
echo "tables: $out/*/table1.md"
