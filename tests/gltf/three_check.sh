#!/usr/bin/env bash
# three.js plays a drape .glb as the run went: one run exported as .glb and as OBJ frames, then
# three_playback.mjs compares the morphed mesh at several frames with the OBJ frames.
# Usage: three_check.sh DRAPE SOURCE_DIR
set -euo pipefail
drape=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run=("$drape" run "$src/scenes/ground.json" --seconds 1 --every 5 --quiet --export)
"${run[@]}" "$tmp/run.glb"
"${run[@]}" "$tmp/frames"
node "$src/tests/gltf/three_playback.mjs" "$tmp/run.glb" "$tmp/frames" 60 0 20 35 60
