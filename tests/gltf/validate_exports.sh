#!/usr/bin/env bash
# Writes .glb files with `drape run` (a sphere; a sphere on a ground plane; no collider; a moving
# ball (animated node); wind in a run stopped by SIGINT) and runs the Khronos glTF validator on them: any error fails.
# Usage: validate_exports.sh DRAPE SOURCE_DIR
set -euo pipefail
drape=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$drape" run "$src/scenes/sphere.json" --seconds 0.5 --every 5 --quiet --export "$tmp/sphere.glb"
"$drape" run "$src/scenes/ground.json" --seconds 0.5 --every 3 --quiet --export "$tmp/ground.glb"
"$drape" run "$src/scenes/hang.json" --seconds 0.1 --quiet --export "$tmp/hang.glb"
"$drape" run "$src/scenes/curtain.json" --seconds 0.8 --every 6 --quiet --export "$tmp/curtain.glb"
# Job control on: without it the background run would start with SIGINT ignored, and a signal
# sent before drape installs its handler (a slow start under the sanitizers) would be lost.
set -m
"$drape" run "$src/scenes/wind.json" --seconds 1000 --every 10 --quiet \
  --export "$tmp/stopped.glb" &
pid=$!
sleep 1
kill -INT $pid
wait $pid || [ $? -eq 130 ]
node "$src/tests/gltf/validate.mjs" "$tmp"/*.glb
