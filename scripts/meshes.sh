#!/usr/bin/env bash
# Remakes the shipped cloth meshes in meshes/ with `drape mesh` (the shapes are made in code:
# src/core/model/shapes.cpp). Run after scripts/build.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
drape=./build/drape
mkdir -p meshes
"$drape" mesh disc --resolution 48 --out meshes/disc.obj --force    # table.json
"$drape" mesh tube --resolution 48 --out meshes/skirt.obj --force   # skirt.json
"$drape" mesh flag --resolution 48 --out meshes/flag.obj --force    # flag.json
