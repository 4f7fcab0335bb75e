#!/usr/bin/env bash
# ctest driver of the real Potree client test (check_potree_client.cjs): writes or converts a
# Potree 2.0 directory, dumps what Parallax's reader gives for it, and has @pnext/three-loader
# read it and compare. Fails (never skips) when node or the npm packages are missing.
#
#   run_client_check.sh handmade TOOL WORKDIR            the hand-made PotreeConverter-style set
#   run_client_check.sh convert  TOOL WORKDIR PARALLAX   `parallax convert tiny.ply -o DIR`
# TOOL is tests/lod/potree_test_tool; WORKDIR is emptied first.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
mode=${1:?mode} tool=${2:?tool} work=${3:?work dir}

if ! command -v node >/dev/null 2>&1; then
  echo "FAILED: node not found: install Debian's nodejs and npm (scripts/install-deps.sh)" >&2
  exit 1
fi
if [[ ! -f "$here/node_modules/@pnext/three-loader/package.json" ||
      ! -f "$here/node_modules/three/package.json" ]]; then
  echo "FAILED: @pnext/three-loader is not installed: run 'npm ci' in $here" \
       "(scripts/install-deps.sh does)" >&2
  exit 1
fi

rm -rf "$work"
mkdir -p "$work"
case $mode in
  handmade)
    "$tool" write-handmade "$work/potree"
    ;;
  convert)
    parallax=${4:?parallax executable}
    # Enough points for a hierarchy deeper than one chunk (proxies), still a second's work.
    "$parallax" generate -o "$work/tiny.ply" --points 300000 --seed 7
    "$parallax" convert "$work/tiny.ply" -o "$work/potree" -q
    ;;
  *)
    echo "run_client_check.sh: unknown mode '$mode'" >&2
    exit 2
    ;;
esac
"$tool" dump "$work/potree" "$work/parallax.json"
node "$here/check_potree_client.cjs" "$work/potree" "$work/parallax.json"
