#!/usr/bin/env bash
# Installs drape into a temporary prefix, builds the programs in examples/ against it by CMake
# (find_package(drape CONFIG)) and by pkg-config (drape.pc), and runs them; checks that every
# installed header compiles on its own with only the installed include folder (so none names a
# private header), and that the installed command and Python module run.
# Usage: package_test.sh BUILD_DIR SOURCE_DIR CXX [PYTHON]
set -euo pipefail
build=$1
src=$2
cxx=$3
python=${4:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null

echo "package: CMake"
cmake -S "$src/examples" -B "$tmp/cmake" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$tmp/cmake" >/dev/null
"$tmp/cmake/falling_cloth"
"$tmp/cmake/falling_denim"

echo "package: pkg-config"
pc=$(find "$prefix" -name drape.pc)
export PKG_CONFIG_PATH
PKG_CONFIG_PATH=$(dirname "$pc")
for example in falling_cloth falling_denim; do
  # shellcheck disable=SC2046 # pkg-config's flags are words
  "$cxx" -std=c++20 -O2 "$src/examples/$example.cpp" -o "$tmp/$example" \
    $(pkg-config --cflags --libs drape)
  "$tmp/$example"
done

echo "package: headers"
for header in "$prefix"/include/drape/*.h; do
  if grep -n '#include "' "$header" | grep -v '#include "drape/'; then
    echo "package: $header names a header that is not drape's public one"
    exit 1
  fi
  # shellcheck disable=SC2046
  echo "#include <drape/$(basename "$header")>" |
    "$cxx" -std=c++20 -fsyntax-only -x c++ - $(pkg-config --cflags drape)
done
ls "$prefix"/include/drape

echo "package: the command and the Python module"
"$prefix/bin/drape" --version
"$prefix/bin/drape" run "$prefix/share/drape/scenes/hang.json" --seconds 0.05 --quiet
if [ -n "$python" ]; then
  module=$(find "$prefix" -name 'drape*.so' -path '*-packages/*')
  PYTHONPATH=$(dirname "$module") "$python" -c \
    "import drape; print('drape', drape.__version__, 'from', drape.__file__)"
fi
