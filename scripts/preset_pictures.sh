#!/usr/bin/env bash
# Renders the README's pictures of every material preset, hung from two corners
# (scenes/hang-denim.json), held by two corners brought together (scenes/held-denim.json) and
# draped over the sphere (scenes/sphere-denim.json), into docs/presets/. Needs a build
# (scripts/build.sh) and EGL; about four minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for preset in denim knit polyester cotton-polyester; do
  for scene in hang held sphere; do
    # The held cloth's folds fall far below where it starts: seen from higher up.
    case $scene in hang) view=(--zoom 2) ;; held) view=(--pitch 30) ;; sphere) view=(--zoom 3) ;; esac
    build/drape render "scenes/$scene-denim.json" --set "cloth.material=\"$preset\"" \
      --size 480x360 "${view[@]}" --every 100000 --out "$work/$scene-$preset" --quiet
    last=$(ls "$work/$scene-$preset"/frame_*.png | tail -1)
    cp "$last" "docs/presets/$scene-$preset.png"
  done
done
