"""The peer of `parallax bench normals`: Open3D's normals of the same file, the same work.

Usage: normals_open3d.py FILE K OUTPUT

Reads FILE with open3d.io.read_point_cloud, estimates every point's normal from its K nearest
points (estimate_normals(KDTreeSearchParamKNN(K)), the point itself included, as `parallax
process --normals K` does), turns them towards +z (orient_normals_to_align_with_direction, as
`--orient up`, the default) and writes OUTPUT (binary PLY, the input's order) with
write_point_cloud. Prints one JSON line: {"points", "seconds": {"read", "normals", "orient", "write"},
"peak_kb"} (peak_kb: /proc/self/status VmHWM). Debian's python3-open3d; a benchmark oracle,
never used by the product.
"""
import json
import sys
import time

import open3d as o3d

from peak_memory import peak_kb


def main():
    path, k, output = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    start = time.perf_counter()
    cloud = o3d.io.read_point_cloud(path)
    if not cloud.has_points():
        sys.exit(f"normals_open3d.py: Open3D read no points from {path}")
    read = time.perf_counter()
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(k))
    estimated = time.perf_counter()
    cloud.orient_normals_to_align_with_direction([0.0, 0.0, 1.0])
    normals = time.perf_counter()
    if not o3d.io.write_point_cloud(output, cloud):
        sys.exit(f"normals_open3d.py: Open3D could not write {output}")
    done = time.perf_counter()
    print(json.dumps({"points": len(cloud.points),
                      "seconds": {"read": read - start, "normals": estimated - read,
                                  "orient": normals - estimated, "write": done - normals},
                      "peak_kb": peak_kb()}))


if __name__ == "__main__":
    main()
