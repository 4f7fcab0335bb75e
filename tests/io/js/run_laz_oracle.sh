#!/usr/bin/env bash
# ctest driver of the laz-perf checks (laz_oracle.cjs). Fails (never skips) when node or the npm
# packages are missing.
#
#   run_laz_oracle.sh writer PARALLAX WORKDIR DATA
#       LAZ written by `parallax convert` must decode in laz-perf to exactly the records of
#       Parallax's LAS output of the same input: a generated scan (point format 2 with extra
#       bytes), in one chunk and in many, and the LAS files of DATA (formats 0-3, extra bytes;
#       formats 6, 7 and 8 through the layered codec).
#   run_laz_oracle.sh files TOOL WORKDIR FILE...
#       laz-perf and Parallax (TOOL: laz_test_tool) must decode each FILE to the same records.
# WORKDIR is emptied first.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
mode=${1:?mode}

if ! command -v node >/dev/null 2>&1; then
  echo "FAILED: node not found: install Debian's nodejs and npm (scripts/install-deps.sh)" >&2
  exit 1
fi
if [[ ! -f "$here/node_modules/laz-perf/package.json" ]]; then
  echo "FAILED: laz-perf is not installed: run 'npm ci' in $here (scripts/install-deps.sh does)" >&2
  exit 1
fi

case $mode in
  writer)
    parallax=${2:?parallax} work=${3:?work dir} data=${4:?data dir}
    rm -rf "$work" && mkdir -p "$work"
    # The files laz-perf compares, LAZ then LAS: all in one Node run at the end (a Node start
    # and laz-perf's module cost about as much as a small file's decode).
    pairs=()
    "$parallax" generate -o "$work/scan.ply" --points 60000 --seed 3
    "$parallax" convert "$work/scan.ply" -o "$work/scan.las" -q
    "$parallax" convert "$work/scan.ply" -o "$work/scan.laz" -q
    "$parallax" convert "$work/scan.ply" -o "$work/scan-small.laz" --laz-chunk 7001 -q
    pairs+=("$work/scan.laz" "$work/scan.las")
    pairs+=("$work/scan-small.laz" "$work/scan.las")
    # LAZ to LAZ too: the twin read from its LAZ, written again.
    for name in point10 point-time point-color point-color-time extrabytes 1815; do
      input="$data/$name.las"
      "$parallax" convert "$input" -o "$work/$name.las" -q
      "$parallax" convert "$input" -o "$work/$name.laz" -q
      pairs+=("$work/$name.laz" "$work/$name.las")
      # The records are kept: laz-perf's decode equals the source's records, byte for byte.
      pairs+=("$work/$name.laz" "$input")
      "$parallax" convert "$work/$name.laz" -o "$work/$name.again.laz" -q
      pairs+=("$work/$name.again.laz" "$input")
    done
    # LAS 1.4 point formats 6 and 7: layered chunks.
    "$parallax" convert "$data/point-time.las" -o "$work/format6.las" --point-format 6 -q
    "$parallax" convert "$data/point-time.las" -o "$work/format6.laz" --point-format 6 -q
    pairs+=("$work/format6.laz" "$work/format6.las")
    "$parallax" convert "$work/scan.ply" -o "$work/format7.las" --las-version 1.4 -q
    "$parallax" convert "$work/scan.ply" -o "$work/format7.laz" --las-version 1.4 --laz-chunk 3000 -q
    pairs+=("$work/format7.laz" "$work/format7.las")
    # Point format 8 (7 and a near-infrared channel): the layered codec's NIR layer, on NIR
    # values that change from point to point (a PLY's "nir" property), and on a scan without
    # NIR (all zero).
    awk 'BEGIN {
      n = 5000
      print "ply\nformat ascii 1.0\nelement vertex " n
      print "property double x\nproperty double y\nproperty double z"
      print "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty ushort nir"
      print "end_header"
      for (i = 0; i < n; i++)
        print (i % 97) * 0.01, int(i / 97) * 0.01, ((i * 7919) % 1000) * 0.001, i % 256,
              (i * 3) % 256, (i * 7) % 256, (i * 2654435761) % 65536
    }' > "$work/nir.ply"
    "$parallax" convert "$work/nir.ply" -o "$work/nir8.las" --point-format 8 -q
    "$parallax" convert "$work/nir.ply" -o "$work/nir8.laz" --point-format 8 --laz-chunk 1000 -q
    pairs+=("$work/nir8.laz" "$work/nir8.las")
    "$parallax" convert "$work/scan.ply" -o "$work/format8.las" --point-format 8 -q
    "$parallax" convert "$work/scan.ply" -o "$work/format8.laz" --point-format 8 --laz-chunk 3000 -q
    pairs+=("$work/format8.laz" "$work/format8.las")
    "$parallax" convert "$data/point-color-time.las.laz" -o "$work/again.laz" --laz-chunk 100 -q
    pairs+=("$work/again.laz" "$work/point-color-time.las")
    node "$here/laz_oracle.cjs" compare "${pairs[@]}"
    ;;
  files)
    tool=${2:?tool} work=${3:?work dir}
    shift 3
    rm -rf "$work" && mkdir -p "$work"
    for file in "$@"; do
      name=$(basename "$file")
      node "$here/laz_oracle.cjs" dump "$file" "$work/$name.laz-perf"
      "$tool" records "$file" "$work/$name.parallax"
      if ! cmp "$work/$name.laz-perf" "$work/$name.parallax"; then
        echo "FAILED: $file: Parallax's records differ from laz-perf's" >&2
        exit 1
      fi
      echo "$file: Parallax's records equal laz-perf's"
    done
    ;;
  *)
    echo "run_laz_oracle.sh: unknown mode '$mode'" >&2
    exit 2
    ;;
esac
