"""The peer of `parallax bench register`: Open3D's point-to-plane ICP on the same two files.

Usage: icp_open3d.py SOURCE TARGET MAX_DISTANCE

Reads both files with open3d.io.read_point_cloud, estimates the target's normals from its 16
nearest points (as `parallax register` does when the target has none), and runs
registration_icp point-to-plane from the identity to convergence (relative fitness and RMSE
1e-9, at most 100 iterations), on the points shifted by the target's bounds' centre (as
`parallax register` works, so that large coordinates keep their precision). Prints one JSON line:
{"transform": [[4 rows of 4]] (SOURCE -> TARGET, world coordinates), "rms", "overlap",
"seconds": {"read", "normals", "icp"}}. Debian's python3-open3d; a benchmark oracle, never used
by the product.
"""
import json
import sys
import time

import numpy as np
import open3d as o3d

from peak_memory import peak_kb


def main():
    source_path, target_path, max_distance = sys.argv[1], sys.argv[2], float(sys.argv[3])
    start = time.perf_counter()
    source = o3d.io.read_point_cloud(source_path)
    target = o3d.io.read_point_cloud(target_path)
    if not source.has_points() or not target.has_points():
        sys.exit(f"icp_open3d.py: Open3D read no points from {source_path} or {target_path}")
    read = time.perf_counter()
    bounds = np.asarray(target.points)
    centre = (bounds.min(axis=0) + bounds.max(axis=0)) / 2
    source.translate(-centre)
    target.translate(-centre)
    target.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(16))
    normals = time.perf_counter()
    reg = o3d.pipelines.registration
    result = reg.registration_icp(
        source, target, max_distance, np.eye(4), reg.TransformationEstimationPointToPlane(),
        reg.ICPConvergenceCriteria(relative_fitness=1e-9, relative_rmse=1e-9, max_iteration=100))
    done = time.perf_counter()
    shift, back = np.eye(4), np.eye(4)
    shift[:3, 3], back[:3, 3] = centre, -centre
    transform = shift @ result.transformation @ back
    print(json.dumps({"transform": transform.tolist(), "rms": result.inlier_rmse,
                      "overlap": result.fitness,
                      "seconds": {"read": read - start, "normals": normals - read,
                                  "icp": done - normals},
                      "peak_kb": peak_kb()}))


if __name__ == "__main__":
    main()
