#!/usr/bin/env bash
# The main job on built-in data: builds Strata and composes the meta-relief paper's Shaped Fabric
# (built-in base + fabric, weights 1.0 / 0.3) into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release
mkdir -p out
build/release/apps/strata/strata compose examples/shaped_fabric.json -o out/shaped_fabric
echo "demo: the Shaped Fabric texture set is in out/shaped_fabric/ (packed.png, depth.png, normal.png, color.png, ao.png, strata.json)"
