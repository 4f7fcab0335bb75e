"""The distributed octree build against the local one, in the same run.

    /usr/bin/python3 bench/bench_distributed.py IN.ply --parallax build/apps/parallax/parallax \
        [--workers 2] [--threads 2] [--tasks 8] [--build-tasks N] [--memory 1024] [--repeat 3] \
        [--out DIR] [--report report.json] [--worker-profile]

Starts a Dask cluster on loopback once (a scheduler and --workers single-threaded workers, as a
cluster is there before a conversion; Dask's statistical worker profiler off, as a deployment
that does not look at the dashboard's profile would set it, unless --worker-profile), then
alternates `parallax convert IN -o DIR/local --threads T` and `python3 -m parallax_dask IN -o
DIR/dask --scheduler ...` (each after a sync, and going first in turns), checks that both outputs are the same bytes, and prints for each run the
wall time, the CPU time (the local process; the driver, its plan and every worker with the tasks it
ran, from /proc), their ratios and the load average (other work on the machine shows there). The
best of each is compared at the end. The last Dask run's report (every task's time) is written for
bench/cost_model.py.
"""

import argparse
import filecmp
import json
import os
import resource
import shutil
import signal
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


def children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def process_cpu(pid):
    """CPU seconds of a process and of the children it has waited for (/proc/PID/stat)."""
    with open(f"/proc/{pid}/stat", encoding="ascii") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    # utime, stime, cutime, cstime: fields 14-17 of proc(5), 12-15 after the name.
    return sum(int(v) for v in fields[11:15]) / os.sysconf("SC_CLK_TCK")


class Cluster:
    def __init__(self, directory, workers, profile=False):
        self.processes = []
        # The workers' statistical profiler samples every thread's stack every 10 ms: about half
        # of an idle worker's CPU here (0.32 against 0.16 CPU s in 10 s). A deployment that does
        # not read the dashboard's profile turns it off in its Dask configuration; the same here.
        worker_env = dict(os.environ)
        if not profile:
            worker_env["DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED"] = "False"
        scheduler_file = os.path.join(directory, "scheduler.json")
        self._start([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host",
                     "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file",
                     scheduler_file])
        while not os.path.exists(scheduler_file):
            time.sleep(0.1)
        with open(scheduler_file, encoding="utf-8") as f:
            self.address = json.load(f)["address"]
        self.workers = [self._start([sys.executable, "-m", "distributed.cli.dask_worker",
                                     self.address, "--nthreads", "1", "--no-nanny",
                                     "--no-dashboard", "--host", "127.0.0.1",
                                     "--local-directory", os.path.join(directory, f"w{i}")],
                                    worker_env)
                        for i in range(workers)]
        from distributed import Client
        with Client(self.address) as client:
            client.wait_for_workers(workers, timeout=60)

    def _start(self, command, env=None):
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                   start_new_session=True, env=env)
        self.processes.append(process)
        return process

    def workers_cpu(self):
        return sum(process_cpu(w.pid) for w in self.workers)

    def stop(self):
        for process in self.processes:
            try:
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            process.wait()


def timed(command, env=None, cluster=None):
    """Wall and CPU seconds of a command (with the cluster's workers' CPU when given)."""
    cpu = children_cpu() + (cluster.workers_cpu() if cluster else 0.0)
    start = time.monotonic()
    subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL)
    wall = time.monotonic() - start
    cpu = children_cpu() + (cluster.workers_cpu() if cluster else 0.0) - cpu
    return wall, cpu


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
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", default="/tmp/big/bench_distributed")
    parser.add_argument("--report", default=None)
    parser.add_argument("--worker-profile", action="store_true",
                        help="keep the Dask workers' statistical profiler on (Dask's default)")
    options = parser.parse_args()
    parallax = os.path.abspath(options.parallax)
    points = points_of(parallax, options.input)
    os.makedirs(options.out, exist_ok=True)
    local_out = os.path.join(options.out, "local", "octree")
    dask_out = os.path.join(options.out, "dask", "octree")
    report = os.path.join(options.out, "report.json")
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    sys.path.insert(0, os.path.join(ROOT, "python"))
    local_times, dask_times = [], []
    cluster_start = time.monotonic()
    cluster = Cluster(options.out, options.workers, options.worker_profile)
    print(f"cluster of {options.workers} workers (profiler "
          f"{'on' if options.worker_profile else 'off'}) started in "
          f"{time.monotonic() - cluster_start:.2f} s (not counted below)", flush=True)
    try:
        for run in range(options.repeat):
            for out in (local_out, dask_out):
                shutil.rmtree(os.path.dirname(out), ignore_errors=True)
            load = os.getloadavg()[0]
            local_command = [parallax, "convert", options.input, "-o", local_out, "--threads",
                             str(options.threads), "--memory", str(options.memory), "-q"]
            dask_command = [sys.executable, "-m", "parallax_dask", options.input, "-o", dask_out,
                            "--scheduler", cluster.address, "--parallax", parallax, "--tasks",
                            str(options.tasks), "--build-tasks",
                            str(options.build_tasks or options.tasks), "--task-threads",
                            str(options.task_threads), "--memory", str(options.memory),
                            "--report", report, "-q"]
            # Each side starts with no dirty pages of the other's output still being written
            # back, and they take turns at going first: otherwise the second of each pair pays
            # for the first's 3 GB of writes.
            times = {}
            for side in (("local", "dask") if run % 2 == 0 else ("dask", "local")):
                os.sync()
                times[side] = (timed(local_command) if side == "local"
                               else timed(dask_command, env, cluster))
            local, dask = times["local"], times["dask"]
            local_times.append(local[0])
            dask_times.append(dask[0])
            identical = same_tree(local_out, dask_out)
            print(f"run {run + 1}: local {local[0]:.2f} s ({points / local[0] / 1e6:.2f} M "
                  f"points/s, {local[1]:.1f} CPU s), dask {dask[0]:.2f} s "
                  f"({points / dask[0] / 1e6:.2f} M points/s, {dask[1]:.1f} CPU s), ratio "
                  f"{local[0] / dask[0]:.3f} (CPU {local[1] / dask[1]:.3f}), identical: "
                  f"{identical}, load average {load:.2f} -> {os.getloadavg()[0]:.2f}",
                  flush=True)
            with open(report, encoding="utf-8") as f:
                ran = json.load(f)
            builds = [t for t in ran["tasks"] if t["stage"] == "build"]
            print("  dask stages: " + ", ".join(f"{s['stage']} {s['seconds']:.2f} s"
                                               for s in ran["stages"]) +
                  f"; builds written in place: {sum(bool(t.get('placed')) for t in builds)}"
                  f" of {len(builds)}", flush=True)
            if not identical:
                sys.exit("the distributed output differs from the local one")
    finally:
        cluster.stop()
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
