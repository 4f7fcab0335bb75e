#!/bin/sh
# Rewrites the renderer's golden images (tests/render/golden/*.png) from the current renderer.
# Run it only after a deliberate change to the picture, then look at every image before committing.
#   scripts/regenerate-golden.sh [BUILD_DIR [FILTER]]   (default: build, every image)
# FILTER is a GoogleTest filter (e.g. 'RenderGolden.Stereo*') that rewrites only those images.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
cmake --build "$build" --target test_render_golden
# Each test that rewrites its image fails on purpose (it compared nothing); what counts here is
# that images were written and nothing else failed.
log=$(mktemp)
PARALLAX_REGENERATE_GOLDEN=1 "$build/tests/render/test_render_golden" \
  --gtest_filter="${2:-*}" >"$log" 2>&1 || true
cat "$log"
written=$(grep -c '^regenerated ' "$log" || true)
failures=$(grep -c ': Failure$' "$log" || true)
other=$((failures - written))
rm -f "$log"
if [ "$written" -eq 0 ] || [ "$other" -ne 0 ]; then
  echo "regenerate-golden.sh: $written image(s) written, $other other failure(s): see above" >&2
  exit 1
fi
echo "$written golden image(s) rewritten in $root/tests/render/golden: review them (git diff --stat)"
