#!/usr/bin/env bash
# Usage: scripts/output-snapshot.sh SPHEREMAP_BINARY OUTPUT_FOLDER [DATA_FOLDER]
# The outputs a change that must not change maps is checked against: a batch of every structure of
# DATA/pdb/paper77 and DATA/pdb/misc at a 1 Å grid, and `map` of every mesh of DATA/meshes (exit codes in
# meshes/exit-codes.txt, messages in meshes/NAME.err). Compare two snapshots with
# scripts/compare-outputs.py (CONTRIBUTING.md, "Changes that must not change the maps"). About a minute
# on 2 cores.
set -uo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 SPHEREMAP_BINARY OUTPUT_FOLDER [DATA_FOLDER, default ../shared/data]" >&2
  exit 1
fi
bin=$(realpath "$1")
out=$2
data=${3:-$(dirname "$0")/../../shared/data}
if [ ! -d "$data/pdb/paper77" ] || [ ! -d "$data/meshes" ]; then
  echo "$0: $data has no pdb/paper77 or meshes folder: give the shared data folder as the third argument" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out/meshes"
# The maps only: a batch draws pictures too since they became its default (binaries from before have no
# --no-pictures, and drew none).
# (The help is read whole first: `grep -q` in a pipe under pipefail can fail on the writer's SIGPIPE.)
batch_help=$("$bin" batch --help 2>/dev/null || true)
no_pictures=""
[[ "$batch_help" == *--no-pictures* ]] && no_pictures=--no-pictures
"$bin" batch "$data/pdb/paper77" "$data/pdb/misc" -o "$out/structures" --grid 1.0 --jobs 2 -q $no_pictures
echo "batch exit $?"
for f in "$data"/meshes/*.obj "$data"/meshes/*.off "$data"/meshes/*.ply; do
  n=$(basename "$f")
  "$bin" map "$f" -o "$out/meshes/$n" -q 2>"$out/meshes/$n.err"
  echo "$n $?" >>"$out/meshes/exit-codes.txt"
done
