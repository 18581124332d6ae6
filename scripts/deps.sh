#!/usr/bin/env bash
# Installs drape's build and test dependencies from Debian's packages (Debian 12 or newer).
# Runs apt-get only when something is missing; uses sudo when not root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev nlohmann-json3-dev libcli11-dev libtinyobjloader-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev clang libclang-rt-dev
  libglfw3-dev libepoxy-dev libglm-dev libimgui-dev
  libegl-dev libegl1 libgl1-mesa-dri libegl-mesa0 libgles-dev xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
