#!/usr/bin/env bash
# Regenerates the committed texture assets from examples/assets/bricks.json
# with the asset step (docs/textures.md). Usage: examples/assets/make_assets.sh [PARALLAX]
set -euo pipefail
cd "$(dirname "$0")"
parallax=${1:-../../build/parallax}
for variant in etc2 pvrtc; do
    rm -rf "bricks_$variant"
    "$parallax" convert --scene bricks.json --format "$variant" --out "bricks_$variant"
done
