#!/usr/bin/env bash
# Maps each input with each objective (`spheremap map --objective O`) and prints the Markdown rows of
# BENCHMARKS.md's "Objectives" table: distortion, certificate, the optimization's steps and times.
#   bench/objectives.sh [INPUT...]   (default: bunny, armadillo, cheburashka and five of the paper's structures;
#                                     SPHEREMAP=path/to/binary, OBJECTIVES="paper area conformal balanced",
#                                     TIME_CAP=seconds: a map that takes longer is stopped and its row says
#                                     "not run", with the vertex count of the paper's map of the input)
set -uo pipefail
cd "$(dirname "$0")/.."
data=../shared/data
inputs=("$@")
[ ${#inputs[@]} -gt 0 ] || inputs=("$data"/meshes/bff_bunny.obj "$data"/meshes/libigl_armadillo.obj
  "$data"/meshes/libigl_cheburashka.off "$data"/pdb/paper77/{1brf,1byz,1ejg,3lzt,1g66}.pdb)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| input | vertices | objective | mean \\|Δangle\\| ° | mean \\|ln area ratio\\| | octant RMS % | certified | iterations (stop) | objective s | total s |"
echo "|---|---:|---|---:|---:|---:|---|---|---:|---:|"
for f in "${inputs[@]}"; do
  for o in ${OBJECTIVES:-paper area conformal balanced}; do
    rm -rf "$out/r"
    cap=()
    [ -n "${TIME_CAP:-}" ] && cap=(timeout "$TIME_CAP")
    "${cap[@]}" "${SPHEREMAP:-./build/spheremap}" map "$f" -o "$out/r" -q --no-pictures --objective "$o" \
      >/dev/null 2>"$out/err"
    code=$?
    if [ "$code" = 124 ] && [ -n "${TIME_CAP:-}" ]; then
      rm -rf "$out/r"
      "${cap[@]}" "${SPHEREMAP:-./build/spheremap}" map "$f" -o "$out/r" -q --no-pictures >/dev/null 2>&1
      vertices=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["mesh"]["vertices"])' \
        "$out/r/report.json" 2>/dev/null)
      echo "| $(basename "$f") | ${vertices:-?} | $o | not run: over the ${TIME_CAP} s time cap | | | | | | |"
      continue
    fi
    if [ ! -f "$out/r/report.json" ]; then
      echo "| $(basename "$f") | | $o | exit $code: $(head -c 200 "$out/err") | | | | | | |"
      continue
    fi
    python3 - "$out/r/report.json" "$(basename "$f")" "$o" <<'PY'
import json, sys
path, name, objective = sys.argv[1:4]
r = json.load(open(path))
d, c, t = r["distortion"], r["certificate"], r["timings_seconds"]
o = r["map"].get("objective")
total = sum(v for v in t.values() if isinstance(v, (int, float)))
weight = f', shape weight {o["shape_weight"]:g}' if o and "shape_weight" in o else ""
stages = f', {o["stages"]} stages{weight}' if o and o.get("stages", 1) > 1 else ""
steps = f'{o["iterations"]} ({o["stop_reason"]}{stages}{"" if o["outcome"] == "optimized" else ", " + o["outcome"]})' if o else "—"
seconds = f'{t["objective"]:.2f}' if o else "—"
print(f'| {name} | {r["mesh"]["vertices"]} | {objective} | {d["angle_distortion_mean_degrees"]:.2f} | '
      f'{d["area_log_ratio_mean"]:.3f} | {d["octant_rms_deviation_percent"]:.2f} | {"yes" if c["certified"] else "**no**"} | '
      f'{steps} | {seconds} | {total:.2f} |')
PY
  done
done
