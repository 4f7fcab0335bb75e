#!/usr/bin/env bash
# The first thing to run: installs the dependencies, builds Release into build/, generates a
# sample scanned scene (2 M points, out/sample.ply) and shows it: in a window when there is a
# display and the viewer is built, else as a headless render (out/sample.png) when `parallax
# render` exists, and always as `parallax info`.
#
#   scripts/demo.sh                  2 M points
#   PARALLAX_DEMO_POINTS=200000 scripts/demo.sh
#   PARALLAX_BUILD_DIR=build-mine scripts/demo.sh    another build tree (default build)
set -euo pipefail

cd "$(dirname "$0")/.."
points=${PARALLAX_DEMO_POINTS:-2000000}
jobs=${PARALLAX_JOBS:-$(nproc)}
sample=out/sample.ply
build_dir=${PARALLAX_BUILD_DIR:-build}

echo "== dependencies"
scripts/install-deps.sh </dev/null

echo "== build (Release, $build_dir/)"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DPARALLAX_UNITY_BUILD=ON
cmake --build "$build_dir" -j "$jobs" --target parallax
parallax=$build_dir/apps/parallax/parallax

echo "== generate $points points into $sample"
mkdir -p out
"$parallax" generate -o "$sample" --points "$points"

echo "== parallax info $sample"
"$parallax" info "$sample"

echo "== parallax render $sample -> out/sample.png"
# A look that shows the scanned surfaces (render's own default is fixed 1-pixel points, unlit):
# round points sized to the local spacing, lit by the normals the generated scene carries.
"$parallax" render "$sample" -o out/sample.png --size-mode adaptive --shape round --lighting
if [[ -n "${DISPLAY:-}" ]]; then
  echo "== parallax view $sample (close the window to finish)"
  exec "$parallax" view "$sample"
fi
