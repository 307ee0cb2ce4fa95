#!/usr/bin/env bash
# Installs the renderers the benchmarks compare against, skipping those already present:
# Blender (Cycles, for `tessera-bench converge --peer cycles`) and Embree 3 (embree_compare),
# and the test meshes of bench/accel/compare_embree.sh's suite: libcgal-demo (CGAL's data:
# scanned elephant, bunny, armadillo, the fandisk CAD part) and assimp-testmodels (a glTF
# engine, an IFC house). Only benchmarks use them; building Tessera and `make test` never do.
# Run as root (or with sudo available). Safe to run repeatedly.
set -euo pipefail

packages=(blender libembree-dev libcgal-demo assimp-testmodels)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-bench-peers: ${packages[*]} present"
  exit 0
fi

echo "install-bench-peers: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# Blender's recommends (fonts, sound, python extras) are not needed headless.
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
