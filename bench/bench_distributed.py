"""The distributed octree build against the local one, in the same run.

    /usr/bin/python3 bench/bench_distributed.py IN.ply --parallax build/apps/parallax/parallax \
        [--workers 2] [--threads 2] [--tasks 8] [--memory 1024] [--repeat 2] [--out DIR] \
        [--report report.json]

Alternates `parallax convert IN -o DIR/local --threads T` and `python3 -m parallax_dask IN -o
DIR/dask --local-workers W` (single-threaded workers, one task per worker at a time), checks
that both outputs are the same bytes, and prints the points per second of each, their ratio and
the load average (other work on the machine shows there). The last Dask run's report (every
task's time) is written for bench/cost_model.py.
"""

import argparse
import filecmp
import json
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def points_of(parallax, path):
    done = subprocess.run([parallax, "info", path, "--json", "-q"], capture_output=True,
                          text=True, check=True)
    return json.loads(done.stdout)["points"]


def same_tree(left, right):
    names = sorted(os.listdir(left))
    return names == sorted(os.listdir(right)) and all(
        filecmp.cmp(os.path.join(left, n), os.path.join(right, n), shallow=False) for n in names)


def timed(command, env=None):
    start = time.monotonic()
    subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL)
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input")
    parser.add_argument("--parallax", required=True)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--threads", type=int, default=2, help="threads of the local build")
    parser.add_argument("--task-threads", type=int, default=1)
    parser.add_argument("--tasks", type=int, default=8)
    parser.add_argument("--build-tasks", type=int, default=0, help="default: --tasks")
    parser.add_argument("--memory", type=int, default=1024)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--out", default="/tmp/big/bench_distributed")
    parser.add_argument("--report", default=None)
    options = parser.parse_args()
    parallax = os.path.abspath(options.parallax)
    points = points_of(parallax, options.input)
    os.makedirs(options.out, exist_ok=True)
    local_out = os.path.join(options.out, "local", "octree")
    dask_out = os.path.join(options.out, "dask", "octree")
    report = os.path.join(options.out, "report.json")
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    local_times, dask_times = [], []
    for run in range(options.repeat):
        for out in (local_out, dask_out):
            shutil.rmtree(os.path.dirname(out), ignore_errors=True)
        local_times.append(timed([parallax, "convert", options.input, "-o", local_out,
                                  "--threads", str(options.threads), "--memory",
                                  str(options.memory), "-q"]))
        dask_times.append(timed([sys.executable, "-m", "parallax_dask", options.input, "-o",
                                 dask_out, "--local-workers", str(options.workers),
                                 "--parallax", parallax, "--tasks", str(options.tasks),
                                 "--build-tasks", str(options.build_tasks or options.tasks),
                                 "--task-threads", str(options.task_threads), "--memory",
                                 str(options.memory), "--report", report, "-q"], env))
        identical = same_tree(local_out, dask_out)
        print(f"run {run + 1}: local {local_times[-1]:.2f} s "
              f"({points / local_times[-1] / 1e6:.2f} M points/s), dask {dask_times[-1]:.2f} s "
              f"({points / dask_times[-1] / 1e6:.2f} M points/s), ratio "
              f"{local_times[-1] / dask_times[-1]:.3f}, identical: {identical}, load average "
              f"{os.getloadavg()[0]:.2f}", flush=True)
        if not identical:
            sys.exit("the distributed output differs from the local one")
    best_local, best_dask = min(local_times), min(dask_times)
    print(f"best: local {points / best_local / 1e6:.2f} M points/s ({options.threads} threads), "
          f"dask {points / best_dask / 1e6:.2f} M points/s ({options.workers} workers x "
          f"{options.task_threads} thread), ratio {best_local / best_dask:.3f}; "
          f"{points} points, --memory {options.memory}, --tasks {options.tasks}")
    if options.report:
        with open(report, encoding="utf-8") as f:
            data = json.load(f)
        data["points"] = points
        data["local_seconds"] = local_times
        data["dask_seconds"] = dask_times
        with open(options.report, "w", encoding="utf-8") as f:
            json.dump(data, f, indent=2)
    shutil.rmtree(options.out, ignore_errors=True)


if __name__ == "__main__":
    main()
