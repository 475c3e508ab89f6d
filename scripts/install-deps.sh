#!/usr/bin/env bash
# Installs, with apt-get, the Debian 12 packages spheremap needs to build and test; does nothing when
# they are all present. Run as root or with sudo available.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
          libeigen3-dev libsuitesparse-dev libcli11-dev nlohmann-json3-dev libfmt-dev
          gemmi-dev tao-pegtl-dev zlib1g-dev libpng-dev libdeflate-dev
          libopenblas0-serial pymol-data libgtest-dev libgmock-dev libbenchmark-dev
          libstb-dev pdb2pqr apbs
          pymol python3-meshio python3-open3d  # the tests that PyMOL, meshio and Open3D read the outputs
          libcairo2-dev libfontconfig-dev libfreetype-dev fonts-dejavu-core  # pictures (render/)
          proj-bin  # PROJ's `proj`, the projections' test oracle
          chromium  # headless Chromium for the viewer's browser test
          firefox-esr xvfb xauth libgl1-mesa-dri)  # Firefox's browser test, in Xvfb with Mesa's software GL
# The viewer (index.html) is bundled at build time with npm packages (viewer/package-lock.json): Debian's
# Node.js and npm only when no npm is on the PATH already (a newer Node.js from elsewhere is kept).
command -v npm >/dev/null || packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
as_root=()
[ "$(id -u)" -eq 0 ] || as_root=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
