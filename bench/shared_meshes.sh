#!/usr/bin/env bash
# Maps every mesh of ../shared/data/meshes with `spheremap map` (default options unless given) and prints
# a Markdown table: size, plain algorithm's folds/collapses, repair, final certificate, distortion, time.
#   bench/shared_meshes.sh [extra spheremap map options...]   (SPHEREMAP=path/to/binary to time another build)
set -uo pipefail
cd "$(dirname "$0")/.."
data=../shared/data/meshes
[ -d "$data" ] || { echo "shared_meshes.sh: $data not found" >&2; exit 1; }
out=$(mktemp -d)
echo "| mesh | vertices | plain folded | plain collapsed | re-weighting rounds | untangling moves | exit | folded | collapsed | area dist. mean % | angle dist. mean ° | octant RMS % | seconds |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for f in "$data"/*.obj "$data"/*.off "$data"/*.ply; do
  name=$(basename "$f")
  rm -rf "$out/r"
  start=$(date +%s.%N)
  "${SPHEREMAP:-./build/spheremap}" map "$f" -o "$out/r" -q "$@" >/dev/null 2>"$out/err"
  code=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  if [ -f "$out/r/report.json" ]; then
    python3 - "$out/r/report.json" "$name" "$code" "$seconds" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); m = r["map"]; c = r["certificate"]; p = r["plain_algorithm_certificate"]; d = r["distortion"]
print(f"| {sys.argv[2]} | {r['mesh']['vertices']} | {p['folded']} | {p['collapsed']} | {m['reweighting_rounds']} | {m['untangling_moves']} | {sys.argv[3]} | {c['folded']} | {c['collapsed']} | {d['area_distortion_mean_percent']:.1f} | {d['angle_distortion_mean_degrees']:.1f} | {d['octant_rms_deviation_percent']:.1f} | {float(sys.argv[4]):.2f} |")
PY
  else
    echo "| $name | | | | | | $code | refused: $(head -c 400 "$out/err" | sed 's/.*error: [^:]*: //; s/[.] .*//; s/|/\\|/g') | | | | | |"
  fi
done
rm -rf "$out"
