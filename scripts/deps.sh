#!/usr/bin/env bash
# Installs drape's build and test dependencies from Debian's packages (Debian 12 or newer).
# Runs apt-get only when something is missing; uses sudo when not root.
set -euo pipefail
cd "$(dirname "$0")/.."

# The Python module (pybind11, NumPy) with its tests (pytest) and the sweep example (Dask
# distributed, matplotlib, tqdm) use Debian's python3. Node.js's npm installs the Khronos glTF
# validator and three.js, which the tests run on .glb exports: from Debian unless a Node.js with
# npm is there.
packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev nlohmann-json3-dev libcli11-dev libtinyobjloader-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev clang libclang-rt-dev libomp-dev
  libglfw3-dev libepoxy-dev libglm-dev libimgui-dev
  libegl-dev libegl1 libgl1-mesa-dri libegl-mesa0 libgles-dev xvfb xauth
  python3 python3-dev pybind11-dev python3-numpy python3-pytest
  python3-distributed python3-matplotlib python3-tqdm
)
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# The glTF validator and three.js, at the versions tests/gltf/package-lock.json pins, into the
# git-ignored tests/gltf/node_modules.
gltf=tests/gltf
for module in gltf-validator three; do
  if [ ! -f "$gltf/node_modules/$module/package.json" ]; then
    echo "deps: installing the glTF validator and three.js (npm) into $gltf/node_modules"
    (cd "$gltf" && npm ci --no-audit --no-fund --loglevel=error)
    break
  fi
done
