#!/usr/bin/env bash
# Maps every structure of ../shared/data/pdb with `spheremap map` (extra options are passed on, e.g.
# --grid 0.25) and prints a Markdown table: atoms, handle repair, area change, certificate, time.
#   bench/structures.sh [spheremap map options...]
set -uo pipefail
cd "$(dirname "$0")/.."
data=../shared/data/pdb
[ -d "$data" ] || { echo "structures.sh: $data not found" >&2; exit 1; }
out=$(mktemp -d)
echo "| structure | atoms | surface vertices | repair | samples changed | area change % | exit | folded | collapsed | seconds |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for f in "$data"/paper77/* "$data"/misc/*; do
  name=$(basename "$(dirname "$f")")/$(basename "$f")
  rm -rf "$out/r"
  start=$(date +%s.%N)
  timeout 600 ./build/spheremap map "$f" -o "$out/r" -q "$@" >/dev/null 2>"$out/err"
  code=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  if [ -f "$out/r/report.json" ]; then
    python3 - "$out/r/report.json" "$name" "$code" "$seconds" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); s = r["structure"]; t = s["topology_repair"]; c = r["certificate"]
print(f"| {sys.argv[2]} | {s['atoms']} | {r['mesh']['vertices']} | {t['method']} | {t['samples_changed']} | {t['area_changed_percent']:+.2f} | {sys.argv[3]} | {c['folded']} | {c['collapsed']} | {float(sys.argv[4]):.1f} |")
PY
  else
    echo "| $name | | | | | | $code | $(head -c 300 "$out/err" | sed 's/.*error: //; s/|/\\|/g') | | $seconds |"
  fi
done
rm -rf "$out"
