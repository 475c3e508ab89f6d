#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build, map the bundled example mesh, then a real
# protein structure (interleukin-2, PDB entry 1SP2 as shipped by Debian's pymol-data) from file to a
# certified sphere map.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh spheremap_cli  # the library and the command only: no tests, no benchmarks
# --force: a second run replaces the first run's outputs (map refuses a folder of an earlier run without it).
./build/spheremap map examples/dumbbell.ply -o out/example --force
echo "outputs in out/example/: surface.ply, sphere.ply (+ .glb), report.json, pictures/, index.html (the viewer)"
./build/spheremap map /usr/share/pymol/data/demo/il2.pdb -o out/il2 --force
echo "outputs in out/il2/: the same, with per-vertex properties, atoms.csv and residues.csv"
