"""The distributed octree build's cost model, from measured task times.

    /usr/bin/python3 bench/cost_model.py REPORT.json [--workers 2,16,64] \
        [--points 1e8,1e11,1e12] [--record-bytes 30] [--memory-mb 1024]

REPORT.json is what `python3 -m parallax_dask ... --report` or bench/bench_distributed.py
--report writes: every task's stage, points and seconds. The model (docs/DISTRIBUTED.md explains
it):

  - per-point stages (scan, count, distribute, build, place): their task seconds summed, per
    point, scale with N and divide over the workers; a stage cannot end before its largest task;
  - the place copy only for the builds that could not write in place: the driver's two lanes
    write in place, so a share of 1 - 2 / workers of the points is copied. Its time per point
    comes from the report's place tasks (per point copied), or --place-ns where it has none
    (two workers copy nothing);
  - per-task overhead: the wall time of a stage beyond its work spread evenly over the workers
    (process start, Dask's dispatch, the shared directory), times the tasks per worker;
  - serial parts: the plan, the cube and chunks merges (per range), and the finish task (top
    levels, hierarchy, metadata: in proportion to N here, an upper bound);
  - the largest task: one chunk's build, max_chunk_points (3/8 of --memory over 74 + record
    bytes per point, convert_count.cpp) at the build's per-point time. A chunk is the unit the
    build cannot split: it bounds the speed-up with Amdahl's serial parts.

It prints the predicted hours for each size and worker count, the disk the work directory
needs at its peak, and the memory per worker.
"""

import argparse
import json

RANGE_STAGES = ("scan", "count", "distribute")
GROUP_STAGES = ("build", "place")


def load(path):
    with open(path, encoding="utf-8") as f:
        report = json.load(f)
    tasks = report["tasks"]
    points = report.get("points") or max(t.get("points", 0) for t in tasks
                                         if t["stage"] == "finish")
    stage_wall = {s["stage"]: s["seconds"] for s in report["stages"]}
    workers = report.get("workers", 2)
    return report, tasks, points, stage_wall, workers


def measure(tasks, points, stage_wall, workers):
    """Per-point seconds of each stage, per-task overhead, serial seconds."""
    model = {"per_point": {}, "largest": {}, "overhead": 0.0}
    overheads = []
    copied = sum(t.get("points", 0) for t in tasks if t["stage"] == "build"
                 and not t.get("placed"))
    for stage in RANGE_STAGES + GROUP_STAGES:
        mine = [t for t in tasks if t["stage"] == stage]
        if not mine:
            continue
        work = sum(t["seconds"] for t in mine)
        # The place tasks' time per point they copied (their builds' points).
        model["per_point"][stage] = work / (copied if stage == "place" and copied else points)
        model["largest"][stage] = max(t["seconds"] for t in mine)
        ideal = max(work / workers, model["largest"][stage])
        overheads.append(max(0.0, stage_wall[stage] - ideal) / (len(mine) / workers))
    model["overhead"] = sum(overheads) / len(overheads)
    model["merge_per_range"] = (stage_wall.get("cube", 0) + stage_wall.get("chunks", 0)) / max(
        1, sum(t["stage"] == "scan" for t in tasks))
    model["finish_per_point"] = stage_wall.get("finish", 0) / points
    return model


def predict(model, n, workers, record_bytes, memory_mb, plan_seconds):
    # Ranges and build groups: 4 per worker to balance the waves, but none under 10^6 points
    # (below that a task's start costs more than its work).
    tasks = max(workers, min(4 * workers, int(n // 1e6)))
    max_chunk = memory_mb * 2**20 * 3 // 8 // (record_bytes + 44)
    largest_chunk = model["per_point"]["build"] * max_chunk
    seconds = plan_seconds + model["merge_per_range"] * tasks
    for stage, per_point in model["per_point"].items():
        work = per_point * n * (max(0.0, 1 - 2 / workers) if stage == "place" else 1)
        floor = largest_chunk if stage == "build" else work / tasks
        seconds += max(work / workers, floor) + model["overhead"] * tasks / workers
    seconds += model["finish_per_point"] * n
    return seconds, largest_chunk


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report")
    parser.add_argument("--workers", default="2,16,64,256,1024")
    parser.add_argument("--points", default="1e8,1e11,1e12")
    parser.add_argument("--record-bytes", type=int, default=30,
                        help="octree.bin record (30: parallax generate's scan layout)")
    parser.add_argument("--memory-mb", type=int, default=1024, help="--memory of every task")
    parser.add_argument("--place-ns", type=float, default=32.0,
                        help="place copy per point copied where the report has no place task "
                        "(32: 3.2 CPU s for 100 M points' parts, measured 2026-11-24)")
    options = parser.parse_args()
    report, tasks, points, stage_wall, measured_workers = load(options.report)
    model = measure(tasks, points, stage_wall, measured_workers)
    model["per_point"].setdefault("place", options.place_ns * 1e-9)
    model["largest"].setdefault("place", 0.0)
    print(f"measured: {points} points on {measured_workers} workers, "
          f"{report.get('seconds', 0):.1f} s")
    for stage, per_point in model["per_point"].items():
        print(f"  {stage:<10} {per_point * 1e9:8.1f} ns/point of one thread, largest task "
              f"{model['largest'][stage]:.2f} s")
    print(f"  overhead per task {model['overhead']:.3f} s, finish "
          f"{model['finish_per_point'] * 1e9:.1f} ns/point (serial)")
    plan_seconds = report.get("plan_seconds", 0.0)
    for n in (float(p) for p in options.points.split(",")):
        disk = 2 * n * options.record_bytes  # shards + parts, or parts + octree.bin
        print(f"\n{n:.0e} points: work directory peak {disk / 1e12:.2f} TB "
              f"(+ the output, {n * options.record_bytes / 1e12:.2f} TB); memory per worker "
              f"{options.memory_mb} MB budget + 16 MB count grid; finish task "
              f"{model['finish_per_point'] * n / 3600:.2f} h alone")
        # A chunk is at least one 128^3 count-grid cell; a terrain fills about 128^2 of them.
        cell = n / 16384
        max_chunk = options.memory_mb * 2**20 * 3 // 8 // (options.record_bytes + 44)
        if cell > max_chunk:
            needed = cell * (options.record_bytes + 44) * 8 / 3 / 2**30
            print(f"  note: a terrain's count-grid cell holds about {cell / 1e6:.0f} M points, "
                  f"more than a {max_chunk / 1e6:.1f} M-point chunk: such cells are built whole, "
                  f"about {needed:.1f} GB per task (a finer grid is the way out)")
        for workers in (int(w) for w in options.workers.split(",")):
            seconds, largest = predict(model, n, workers, options.record_bytes,
                                       options.memory_mb, plan_seconds)
            # One process copies nothing: no place stage in the serial time.
            serial = (sum(v for k, v in model["per_point"].items() if k != "place") * n +
                      model["finish_per_point"] * n)
            print(f"  {workers:5d} workers: {seconds / 3600:8.2f} h = {seconds:9.0f} s "
                  f"(speed-up {serial / seconds:6.1f}; largest task {largest:.1f} s)")


if __name__ == "__main__":
    main()
