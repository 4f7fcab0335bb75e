#!/usr/bin/python3
"""`parallax register` against Open3D's registration_icp (point-to-plane) on the same clouds.

Usage: compare_open3d.py PARALLAX DATA_DIR WORK_DIR

The clouds: copc.js's ellipsoid.laz (100 000 points at x = -8 242 746, Web Mercator), written as a
PLY by `parallax process`, split into its even points (the target) and its odd points moved by a
known rigid motion (the source), so no source point has a twin in the target. Open3D 0.16
(Debian's python3-open3d) runs on the same points shifted by the target's bounds' centre (as
Parallax works internally: Open3D would lose digits at these coordinates), with target normals from
estimate_normals(KNN(16)) and the same maximum distance, to convergence. The two transforms must
put every source point within 1 mm of each other and differ by less than 0.01 degree, and both
must recover the known motion to within the scan's sampling (5 cm, 0.05 degree); their RMS and
overlap must agree to 1e-3 relative. Prints both transforms and each tool's time.
"""
import json
import math
import pathlib
import subprocess
import sys
import time

import numpy as np
import open3d as o3d


def rotation(axis, degrees):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    a = math.radians(degrees)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)


def angle_degrees(m):
    c = max(-1.0, min(1.0, (np.trace(m[:3, :3]) - 1) / 2))
    return math.degrees(math.acos(c))


def apply(m, points):
    return points @ m[:3, :3].T + m[:3, 3]


def write_ply(path, points):
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    if not o3d.io.write_point_cloud(str(path), cloud, write_ascii=False):
        sys.exit(f"cannot write {path}")


def main():
    parallax, data, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    full = work / "ellipsoid.ply"
    subprocess.run([parallax, "process", str(data / "laz" / "ellipsoid.laz"), "-o", str(full),
                    "--subsample", "random:100000", "-q"], check=True)
    points = np.asarray(o3d.io.read_point_cloud(str(full)).points)
    if len(points) != 100000:
        sys.exit(f"{full}: expected 100000 points, read {len(points)}")
    target, moved = points[0::2], points[1::2]
    centre = (target.min(axis=0) + target.max(axis=0)) / 2
    truth = np.eye(4)
    truth[:3, :3] = rotation([1, 2, 3], 1.0)
    truth[:3, 3] = centre + np.array([0.6, -0.4, 0.3]) - truth[:3, :3] @ centre
    source = apply(np.linalg.inv(truth), moved)
    write_ply(work / "target.ply", target)
    write_ply(work / "source.ply", source)
    max_distance = 10.0

    start = time.perf_counter()
    out = subprocess.run([parallax, "register", str(work / "source.ply"), str(work / "target.ply"),
                          "--max-distance", str(max_distance), "--json"],
                         check=True, capture_output=True, text=True).stdout
    parallax_seconds = time.perf_counter() - start
    ours = json.loads(out)
    ours_m = np.array(ours["transform"])

    start = time.perf_counter()
    t = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(target - centre))
    s = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(source - centre))
    t.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(16))
    reg = o3d.pipelines.registration
    result = reg.registration_icp(
        s, t, max_distance, np.eye(4), reg.TransformationEstimationPointToPlane(),
        reg.ICPConvergenceCriteria(relative_fitness=1e-12, relative_rmse=1e-12,
                                   max_iteration=1000))
    open3d_seconds = time.perf_counter() - start
    shift, back = np.eye(4), np.eye(4)
    shift[:3, 3], back[:3, 3] = centre, -centre
    theirs_m = shift @ result.transformation @ back

    disagreement = np.abs(np.linalg.norm(apply(ours_m, source) - apply(theirs_m, source), axis=1))
    report = {
        "parallax": {"transform": ours_m.tolist(), "rms": ours["rms"],
                     "overlap": ours["overlap"], "seconds": parallax_seconds},
        "open3d": {"transform": theirs_m.tolist(), "rms": result.inlier_rmse,
                   "overlap": result.fitness, "seconds": open3d_seconds},
        "largest_point_disagreement": float(disagreement.max()),
        "angle_between_degrees": angle_degrees(np.linalg.inv(ours_m) @ theirs_m),
        "parallax_vs_truth_degrees": angle_degrees(np.linalg.inv(ours_m) @ truth),
        "parallax_vs_truth_largest": float(np.linalg.norm(
            apply(ours_m, source) - apply(truth, source), axis=1).max()),
    }
    print(json.dumps(report, indent=1))
    failures = []
    if report["largest_point_disagreement"] >= 1e-3:
        failures.append("the two transforms put a source point more than 1 mm apart")
    if report["angle_between_degrees"] >= 0.01:
        failures.append("the two rotations differ by 0.01 degree or more")
    if report["parallax_vs_truth_degrees"] >= 0.05 or report["parallax_vs_truth_largest"] >= 0.05:
        failures.append("Parallax is not within 5 cm and 0.05 degree of the known motion")
    if abs(ours["rms"] - result.inlier_rmse) > 1e-3 * result.inlier_rmse:
        failures.append("RMS differs by more than 1e-3 relative")
    if abs(ours["overlap"] - result.fitness) > 1e-3:
        failures.append("overlap differs by more than 1e-3")
    if failures:
        sys.exit("; ".join(failures))


if __name__ == "__main__":
    main()
