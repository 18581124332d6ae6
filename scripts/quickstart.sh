#!/usr/bin/env bash
# The first command for a newcomer: install, build, and run the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
exec ./build/drape run scenes/hang.json
