#!/bin/sh
# Rewrites the renderer's golden images (tests/render/golden/*.png) from the current renderer.
# Run it only after a deliberate change to the picture, then look at every image before committing.
#   scripts/regenerate-golden.sh [BUILD_DIR [FILTER]]   (default: build, every image)
# FILTER is a GoogleTest filter (e.g. 'RenderGolden.Stereo*') that rewrites only those images.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
cmake --build "$build" --target test_render_golden
PARALLAX_REGENERATE_GOLDEN=1 "$build/tests/render/test_render_golden" \
  --gtest_filter="${2:-*}"
echo "golden images rewritten in $root/tests/render/golden: review them (git diff --stat)"
