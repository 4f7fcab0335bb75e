#!/usr/bin/env bash
# ctest driver of the copc.js checks (copc_oracle.cjs) of Parallax's COPC output. Fails (never
# skips) when node or the npm packages are missing.
#
#   run_copc_oracle.sh PARALLAX WORKDIR DATA
#       A generated scan (LAS 1.4, point format 7 with extra bytes) converted to COPC through the
#       builder, and its Potree directory re-encoded node by node, must each hold exactly the
#       LAS file's points (copc.js walks every hierarchy page, laz-perf decodes every chunk,
#       and reads the file front to back through its variable LAZ chunk table);
#       so must the real COPC file DATA/simple.copc.laz written again by Parallax, with its WKT.
# WORKDIR is emptied first.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
parallax=${1:?parallax} work=${2:?work dir} data=${3:?data dir}

if ! command -v node >/dev/null 2>&1; then
  echo "FAILED: node not found: install Debian's nodejs and npm (scripts/install-deps.sh)" >&2
  exit 1
fi
for package in copc laz-perf; do
  if [[ ! -f "$here/node_modules/$package/package.json" ]]; then
    echo "FAILED: $package is not installed: run 'npm ci' in $here (scripts/install-deps.sh does)" >&2
    exit 1
  fi
done

rm -rf "$work" && mkdir -p "$work"
# 150 000 points: a tree of six levels, so the root page has child pages.
"$parallax" generate -o "$work/scan.ply" --points 150000 --seed 5
"$parallax" convert "$work/scan.ply" -o "$work/scan.las" --las-version 1.4 -q
"$parallax" convert "$work/scan.las" -o "$work/scan.copc.laz" -q
node "$here/copc_oracle.cjs" check "$work/scan.copc.laz" "$work/scan.las"
# Between the octree formats: the Potree directory of the same file, node by node to COPC.
"$parallax" convert "$work/scan.las" -o "$work/scan-potree" -q
"$parallax" convert "$work/scan-potree" -o "$work/from-potree.copc.laz" -q
node "$here/copc_oracle.cjs" check "$work/from-potree.copc.laz" "$work/scan.las"
# A real COPC file (untwine's, with a WKT CRS) read plainly and written again.
"$parallax" convert "$data/simple.copc.laz" -o "$work/simple.las" -q
"$parallax" convert "$data/simple.copc.laz" -o "$work/simple.copc.laz" -q
node "$here/copc_oracle.cjs" check "$work/simple.copc.laz" "$work/simple.las"
node "$here/copc_oracle.cjs" summary "$data/simple.copc.laz"
node "$here/copc_oracle.cjs" summary "$data/ellipsoid.copc.laz"
