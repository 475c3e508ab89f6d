#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build, and map the bundled example mesh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
./build/spheremap map examples/dumbbell.ply -o out/example
echo "outputs: out/example/surface.ply out/example/sphere.ply out/example/report.json"
