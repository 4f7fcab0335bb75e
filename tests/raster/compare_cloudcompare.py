"""`parallax raster` against CloudCompare's -RASTERIZE on the same points, same cells, same value.

Usage: compare_cloudcompare.py PARALLAX DATA_DIR WORK_DIR

1815.laz (1 247 real airborne points over a kilometre) as x y z text (`parallax convert`:
Debian's CloudCompare 2.11 reads no LAS), rasterized by CloudCompare (Debian's cloudcompare, run
headless: -SILENT, QT_QPA_PLATFORM=offscreen) with -GRID_STEP 20 -PROJ MIN into a cloud of one
point a filled cell (-OUTPUT_CLOUD: Debian's build has no GDAL for -OUTPUT_RASTER_Z), and by
`parallax raster --value min` on the LAZ file itself. CloudCompare centres its cells on the
bounding box's minimum corner plus multiples of the step, so Parallax's --bounds start half a
cell below the minimum and take CloudCompare's grid size: every cell must then be filled in both
or in neither, with the same lowest z (within float32's rounding at z about 100 m).
"""
import os
import re
import subprocess
import sys
from pathlib import Path

STEP = 20.0


def main():
    parallax, data, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    laz = data / "laz" / "1815.laz"
    subprocess.run([parallax, "convert", str(laz), "-o", str(work / "all.xyz"), "-q"], check=True)
    rows = [line.split() for line in open(work / "all.xyz")][1:]  # a header line of names
    with open(work / "points.xyz", "w") as out:
        for r in rows:
            out.write(f"{r[0]} {r[1]} {r[2]}\n")
    min_x = min(float(r[0]) for r in rows)
    min_y = min(float(r[1]) for r in rows)

    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    log = subprocess.run(
        ["CloudCompare", "-SILENT", "-NO_TIMESTAMP", "-AUTO_SAVE", "OFF", "-O", "-GLOBAL_SHIFT",
         "AUTO", str(work / "points.xyz"), "-RASTERIZE", "-GRID_STEP", str(STEP), "-PROJ", "MIN",
         "-OUTPUT_CLOUD", "-C_EXPORT_FMT", "ASC", "-PREC", "8", "-SAVE_CLOUDS", "FILE",
         str(work / "cloudcompare.asc")],
        env=env, capture_output=True, text=True, check=True).stdout
    size = re.search(r"Grid size: (\d+) x (\d+)", log)
    if not size:
        sys.exit("CloudCompare printed no grid size:\n" + log)
    width, height = int(size.group(1)), int(size.group(2))
    x0, y0 = min_x - STEP / 2, min_y - STEP / 2
    bounds = f"{x0!r},{y0!r},{x0 + width * STEP!r},{y0 + height * STEP!r}"
    subprocess.run([parallax, "raster", str(laz), "-o", str(work / "parallax.tif"), "--resolution",
                    str(STEP), "--value", "min", "--bounds", bounds, "--returns", "all", "-q"],
                   check=True)
    subprocess.run(["gdal_translate", "-q", "-of", "XYZ", str(work / "parallax.tif"),
                    str(work / "parallax.xyz")], check=True)

    ours = {}
    for line in open(work / "parallax.xyz"):
        x, y, z = map(float, line.split())
        if z != -9999:
            ours[(round((x - x0) / STEP - 0.5), round((y - y0) / STEP - 0.5))] = z
    theirs = {}
    for line in open(work / "cloudcompare.asc"):
        x, y, z = map(float, line.split()[:3])
        theirs[(round((x - min_x) / STEP), round((y - min_y) / STEP))] = z
    only_ours, only_theirs = set(ours) - set(theirs), set(theirs) - set(ours)
    worst = max(abs(ours[k] - theirs[k]) for k in set(ours) & set(theirs))
    print(f"grid {width} x {height}: {len(ours)} cells filled by Parallax, {len(theirs)} by "
          f"CloudCompare, {len(only_ours)} and {len(only_theirs)} only in one; largest "
          f"difference {worst:.3g}")
    failures = []
    if (width, height) != (51, 51):
        failures.append(f"CloudCompare's grid is {width} x {height}, not 51 x 51")
    if len(theirs) < 900:
        failures.append(f"CloudCompare filled only {len(theirs)} cells")
    if only_ours or only_theirs:
        failures.append(f"cells filled in one only: {sorted(only_ours)[:5]} {sorted(only_theirs)[:5]}")
    if worst > 2e-5:  # float32 spacing at 100 m is 7.6e-6
        failures.append(f"a cell's lowest z differs by {worst}")
    if failures:
        sys.exit("; ".join(failures))


if __name__ == "__main__":
    main()
