#!/usr/bin/env bash
# A 0.5 m elevation raster (lowest point a cell) of a generated aerial scan, by `parallax raster`
# and by gdal_grid (minimum within half a cell of each centre) on the same points and the same
# grid, in the same run: wall time and peak memory from /usr/bin/time -v, and the ratio.
# (CloudCompare 2.11's -RASTERIZE, as Debian builds it, wrote no raster here: not compared.)
#
#   scripts/bench-raster.sh [POINTS (default 20000000)] [WORK_DIR]
#
# Needs a built build/apps/parallax/parallax, gdal-bin and /usr/bin/time (Debian's `time`).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
parallax="$root/build/apps/parallax/parallax"
points="${1:-20000000}"
work="${2:-/tmp/parallax-bench-raster}"
mkdir -p "$work"
cd "$work"

if [[ ! -f "cloud-$points.ply" ]]; then
  "$parallax" generate -o "cloud-$points.ply" --points "$points" --scene aerial -q
fi
# gdal_grid reads points through OGR: a CSV with its VRT (what a user of GDAL would write).
if [[ ! -f "cloud-$points.csv" ]]; then
  "$parallax" convert "cloud-$points.ply" -o "cloud-$points.csv" --properties x,y,z -q
fi
cat > cloud.vrt <<VRT
<OGRVRTDataSource><OGRVRTLayer name="cloud"><SrcDataSource>$work/cloud-$points.csv</SrcDataSource>
<SrcLayer>cloud-$points</SrcLayer>
<GeometryType>wkbPoint</GeometryType>
<GeometryField encoding="PointFromColumns" x="x" y="y" z="z"/></OGRVRTLayer></OGRVRTDataSource>
VRT

measure() {  # NAME COMMAND...: prints "NAME seconds peak_MB"
  local name="$1"
  shift
  /usr/bin/time -v "$@" 2>"time-$name.txt" >/dev/null
  local wall peak
  wall=$(grep "Elapsed (wall clock)" "time-$name.txt" | awk '{print $NF}' |
    awk -F: '{ if (NF == 3) print $1 * 3600 + $2 * 60 + $3; else print $1 * 60 + $2 }')
  peak=$(grep "Maximum resident set size" "time-$name.txt" | awk '{print int($NF / 1024)}')
  echo "$name $wall $peak"
}

echo "load: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores, $points points"
ours_ply=$(measure parallax-ply "$parallax" raster "cloud-$points.ply" -o dtm-parallax.tif \
  --resolution 0.5 --value min -q)
ours_csv=$(measure parallax-csv "$parallax" raster "cloud-$points.csv" -o dtm-parallax-csv.tif \
  --resolution 0.5 --value min -q)
# The same grid for gdal_grid: Parallax's extent and size, read back from its file.
read -r left top columns rows < <(gdalinfo -json dtm-parallax.tif | python3 -c '
import json, sys
i = json.load(sys.stdin)
print(i["geoTransform"][0], i["geoTransform"][3], i["size"][0], i["size"][1])')
right=$(python3 -c "print($left + $columns * 0.5)")
bottom=$(python3 -c "print($top - $rows * 0.5)")
gdal=$(measure gdal_grid gdal_grid -q -a minimum:radius1=0.25:radius2=0.25:nodata=-9999 \
  -txe "$left" "$right" -tye "$top" "$bottom" -outsize "$columns" "$rows" -ot Float32 \
  -co TILED=YES -co COMPRESS=DEFLATE -l cloud cloud.vrt dtm-gdal.tif)
# Both rasters must hold the same cells with a value, or a failed read would pass as fast.
for f in dtm-parallax.tif dtm-gdal.tif; do
  echo "$f: $(gdalinfo -stats "$f" | grep STATISTICS_VALID_PERCENT | tr -d ' ')"
done
echo "$ours_ply"
echo "$ours_csv"
echo "$gdal"
python3 - "$ours_ply" "$ours_csv" "$gdal" <<'PY'
import sys
rows = [line.split() for line in sys.argv[1:]]
g = float(rows[2][1])
for name, wall, peak in rows[:2]:
    print(f"{name}: {float(wall):.2f} s, {peak} MB; gdal_grid / parallax time: {g / float(wall):.1f}x")
PY
