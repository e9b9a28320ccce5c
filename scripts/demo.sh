#!/usr/bin/env bash
# The main job on built-in data: builds Strata and renders the meta-relief paper's Fig. 1(b), the Utah
# teapot with the Shaped Fabric meta-relief (built-in base + fabric, weights 1.0 / 0.3), texture-space AO,
# one light and self-shadowing, to out/teapot.png (1280x720, antialiased), headless through EGL.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release
build/release/apps/strata/strata render
echo "demo: the picture is out/teapot.png"
