#!/usr/bin/env bash
# Remakes the README's pictures in docs/ with drape itself: the viewer (under xvfb-run when no
# display is set), two `drape render` frames, and a run exported as .glb played back in Blender
# (where Blender is installed: apt-get install blender). Run after scripts/build.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
drape=./build/drape
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

display=()
[ -n "${DISPLAY:-}" ] || display=(xvfb-run -a -s "-screen 0 1280x1024x24")

# The viewer on the default scene, its bottom-right corner pulled toward the eye (a scripted
# drag: press on the corner's pixel at the start, drag up and right, hold).
"${display[@]}" "$drape" view scenes/hang.json --frames 120 --size 1100x650 \
  --drag 921,552,1040,420 --screenshot docs/viewer.png

"$drape" render scenes/wind.json --frames 150 --every 150 --size 800x450 --yaw -35 --pitch 12 \
  --zoom 1 --quiet --out "$tmp/wind"
cp "$tmp/wind/frame_00150.png" docs/wind.png

"$drape" render scenes/sphere.json --frames 150 --every 150 --size 800x450 --pitch 2 --zoom 3 \
  --quiet --out "$tmp/sphere"
cp "$tmp/sphere/frame_00150.png" docs/sphere.png

# Cloth of any shape: the shipped mesh scenes after 4 s.
for scene in table skirt flag; do
  "$drape" render "scenes/$scene.json" --frames 240 --every 240 --size 640x400 --quiet \
    --out "$tmp/$scene"
  cp "$tmp/$scene/frame_00240.png" "docs/$scene.png"
done

# A coarse cloth on a cube balanced on its corner, held out by the feature contacts.
"$drape" render scenes/corner.json --frames 90 --every 90 --size 500x400 --pitch 25 --zoom 2.5 \
  --quiet --out "$tmp/corner"
cp "$tmp/corner/frame_00090.png" docs/corner.png

# Self-collision: the pile after 4 s without and with it.
for sc in false true; do
  "$drape" render scenes/pile.json --set cloth.self_collision=$sc --frames 240 --every 240 \
    --size 640x400 --pitch 60 --zoom 4 --quiet --out "$tmp/pile-$sc"
done
cp "$tmp/pile-false/frame_00240.png" docs/pile-off.png
cp "$tmp/pile-true/frame_00240.png" docs/pile.png

# A ball at 10 m/s pushing into the curtain (seen from the side it comes from), and a cloth
# over the torus mesh collider (meshes/torus.obj, made by scripts/torus.py).
"$drape" render scenes/curtain.json --frames 38 --every 38 --size 640x400 --yaw 130 --pitch 10 \
  --zoom 1 --quiet --out "$tmp/curtain"
cp "$tmp/curtain/frame_00038.png" docs/curtain.png
"$drape" render scenes/torus.json --frames 240 --every 240 --size 640x400 --pitch 40 --zoom 2 \
  --quiet --out "$tmp/torus"
cp "$tmp/torus/frame_00240.png" docs/torus.png

# The ground scene exported as one .glb, imported by Blender and rendered (Eevee) at 0.5, 1.4
# and 3 s of its animation.
if command -v blender >/dev/null; then
  "$drape" run scenes/ground.json --seconds 3 --every 2 --quiet --export "$tmp/ground.glb"
  blender -b --factory-startup --python-exit-code 1 --python scripts/blender_render.py -- \
    "$tmp/ground.glb" "$tmp/blender.png" 0.5 1.4 3.0 >/dev/null 2>&1
  cp "$tmp/blender.png" docs/blender.png
else
  echo "pictures: docs/blender.png not remade: blender is not installed"
fi

ls -l docs/*.png
