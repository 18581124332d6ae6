#!/usr/bin/env bash
# Checks by Blender that drape's caches play back as the run went: one run exported as .glb,
# as .pc2 with its rest mesh, and as OBJ frames, then check_caches.py inside Blender.
# Usage: blender_check.sh DRAPE SOURCE_DIR
set -euo pipefail
drape=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run=("$drape" run "$src/scenes/hang.json" --seconds 1 --every 5 --quiet --export)
"${run[@]}" "$tmp/run.glb"
"${run[@]}" "$tmp/run.pc2"
"${run[@]}" "$tmp/frames"
blender -b --factory-startup --python-exit-code 1 \
  --python "$src/tests/blender/check_caches.py" -- "$tmp"
