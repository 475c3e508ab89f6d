#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build, map the bundled example mesh, then a real
# protein structure (interleukin-2, PDB entry 1SP2 as shipped by Debian's pymol-data) from file to a
# certified sphere map.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh spheremap_cli  # the library and the command only: no tests, no benchmarks
./build/spheremap map examples/dumbbell.ply -o out/example
echo "outputs: out/example/surface.ply out/example/sphere.ply out/example/report.json"
./build/spheremap map /usr/share/pymol/data/demo/il2.pdb -o out/il2
echo "outputs: out/il2/surface.ply out/il2/sphere.ply out/il2/report.json (with per-vertex atom provenance)"
