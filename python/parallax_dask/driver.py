"""The distributed octree build: the plan, then its stages as Dask tasks.

The stages run in order, each as one task per range or group of chunks:

    scan -> cube -> count -> chunks -> distribute -> build -> place -> finish

Every stage needs all of the one before it (the cube needs every range's bounds, a chunk's
build every range's shard of it), so the graph is a chain of fan-outs and merges, and the
driver submits a stage once the one before it is complete. Tasks run `parallax convert-task`
on the workers; the files between them are in the plan's work directory, which every worker
must see at the same path (a shared directory: NFS, Lustre, a POSIX mount of an object store).
"""

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import time
import uuid

import cloudpickle
from distributed import Client, wait

from . import tasks

# The tasks are sent to the workers by value: the workers need Dask and the parallax
# executable, not this package on their Python path.
cloudpickle.register_pickle_by_value(tasks)

STAGES = ("scan", "cube", "count", "chunks", "distribute", "build", "place", "finish")


class ConversionError(Exception):
    """A failed conversion; status 2 for bad input (the task's own message), 1 otherwise."""

    def __init__(self, message, status):
        super().__init__(message)
        self.status = status


class Progress:
    """One line per stage on stderr: redrawn in place on a terminal, printed once otherwise."""

    def __init__(self, quiet):
        self.quiet = quiet
        self.tty = sys.stderr.isatty()

    def update(self, stage, done, total, started):
        if self.quiet or not self.tty:
            return
        width = 30
        filled = width * done // max(total, 1)
        sys.stderr.write(f"\r{stage:<10} [{'#' * filled}{'.' * (width - filled)}] "
                         f"{done}/{total} tasks {time.monotonic() - started:6.1f} s")
        sys.stderr.flush()

    def finish(self, stage, total, seconds):
        if self.quiet:
            return
        if self.tty:
            sys.stderr.write("\r\033[K")
        sys.stderr.write(f"{stage:<10} {total} tasks in {seconds:.2f} s\n")
        sys.stderr.flush()


def write_plan(options, work_dir):
    """`parallax convert --plan` on this machine (headers only); returns the plan's path."""
    command = [options.parallax, "convert", "--plan", *options.inputs, "-o", options.output,
               "--work-dir", work_dir, "--tasks", str(options.tasks), "--build-tasks",
               str(options.build_tasks or options.tasks), "-q"]
    for flag, value in (("--memory", options.memory), ("--sampling", options.sampling),
                        ("--spacing", options.spacing), ("--columns", options.columns),
                        ("--classes", options.classes), ("--clip-box", options.clip_box),
                        ("--clip-mode", options.clip_mode)):
        if value is not None:
            command += [flag, str(value)]
    try:
        done = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as error:
        raise ConversionError(f"cannot run {options.parallax}: {error}", 1) from error
    if done.returncode != 0:
        raise ConversionError(done.stderr.strip(), 2 if done.returncode == 2 else 1)
    return json.loads(done.stdout.strip().splitlines()[-1])["plan"]


def stage_parts(stage, work_dir):
    """How many tasks a stage has: the plan's ranges, chunks.json's groups, or one."""
    if stage in ("scan", "count", "distribute"):
        with open(os.path.join(work_dir, "plan.json"), encoding="utf-8") as plan:
            return len(json.load(plan)["ranges"])
    if stage in ("build", "place"):
        with open(os.path.join(work_dir, "chunks.json"), encoding="utf-8") as chunks:
            return len(json.load(chunks)["groups"])
    return 1


class SubmitAll:
    """The tasks of a stage all submitted at once, Dask spreading them."""

    def __init__(self, parts):
        self.parts = list(parts)
        self.total = len(self.parts)

    def first(self, _slots):
        parts, self.parts = self.parts, []
        return parts

    def next(self, _finished):
        return None


class BuildFromBothEnds:
    """The builds in the order that lets each write straight into octree.bin.

    A build writes into the final file when it knows where its part goes: below chunks.json's
    split, after the parts of the groups before it, so those must be done; from the split on,
    before the parts of the groups after it. So the builds run as two lanes, one group after the
    other up from the first group and down from the last, one task per worker in flight: a lane
    goes on with the group next to the one it finished. With two workers every build writes in
    place; with more, the builds beyond the two lanes write parts that the place stage copies."""

    def __init__(self, groups, split):
        self.lower = list(range(split))
        self.upper = list(range(groups - 1, split - 1, -1))
        self.split = split
        self.total = groups

    def first(self, slots):
        """A task for each worker, from the lower and upper lanes in turn."""
        parts = []
        while len(parts) < max(slots, 1) and (self.lower or self.upper):
            take_lower = bool(self.lower) and (len(parts) % 2 == 0 or not self.upper)
            parts.append((self.lower if take_lower else self.upper).pop(0))
        return parts

    def next(self, finished):
        lane, other = (self.lower, self.upper) if finished < self.split else (self.upper, self.lower)
        if lane:
            return lane.pop(0)
        return other.pop(0) if other else None


def build_schedule(work_dir):
    with open(os.path.join(work_dir, "chunks.json"), encoding="utf-8") as chunks:
        plan = json.load(chunks)
    return BuildFromBothEnds(len(plan["groups"]), plan["split"])


# How often the driver looks whether a task held off one worker can still run anywhere.
RESTRICTION_CHECK_SECONDS = 2.0


def run_stage(client, options, plan, stage, schedule, progress, run_id):
    """Runs the tasks of one stage in the schedule's order (SubmitAll, BuildFromBothEnds);
    returns their results. A failed task runs again (on another worker when there is one) up
    to options.retries times; bad input stops at once.

    The task run again is restricted strictly to the other workers: a loose restriction is
    only a preference, and Dask's work stealing hands such a task to the idle worker it just
    failed on. Should every other worker leave, the task would wait for them forever, so the
    driver looks every few seconds and then lets it run anywhere."""
    started = time.monotonic()
    attempts = {}
    pending = {}  # future -> part
    restricted = {}  # future -> the workers it may run on

    def submit(part, avoid=None, again=False):
        if not again:
            attempts[part] = attempts.get(part, 0) + 1
        workers = None
        if avoid:
            workers = [w for w in client.scheduler_info()["workers"] if w != avoid] or None
        placement = {"workers": workers, "allow_other_workers": False} if workers else {}
        key = f"parallax-{stage}-{part}-{run_id}-{attempts[part]}" + ("-anywhere" if again else "")
        future = client.submit(tasks.run_convert_task, options.parallax, stage, plan, part,
                               options.task_threads, key=key, pure=False, **placement)
        pending[future] = part
        if workers:
            restricted[future] = set(workers)
        return future

    def release_stranded():
        """A task restricted to workers that have all left runs anywhere instead."""
        present = set(client.scheduler_info()["workers"])
        for future, workers in list(restricted.items()):
            if future.status == "pending" and not workers & present:
                del restricted[future]
                part = pending.pop(future)
                future.cancel()
                submit(part, again=True)

    parts = schedule.total
    for part in schedule.first(len(client.scheduler_info()["workers"])):
        submit(part)
    results = []
    progress.update(stage, 0, parts, started)
    while pending:
        try:
            done, _ = wait(list(pending), timeout=RESTRICTION_CHECK_SECONDS,
                           return_when="FIRST_COMPLETED")
        except TimeoutError:  # asyncio's, the same class since Python 3.11
            release_stranded()
            continue
        for future in done:
            part = pending.pop(future)
            restricted.pop(future, None)
            try:
                result = future.result()
            except Exception as error:  # the worker died too often with it (KilledWorker), ...
                result = {"stage": stage, "part": part,
                          "error": f"{type(error).__name__}: {error}"}
            if "input_error" in result:
                client.cancel(list(pending))
                raise ConversionError(result["input_error"], 2)
            if "error" in result:
                if attempts[part] > options.retries:
                    client.cancel(list(pending))
                    raise ConversionError(f"{stage} task {part} failed {attempts[part]} times; "
                                          f"the last time: {result['error']}", 1)
                if not options.quiet:
                    sys.stderr.write(f"\n{stage} task {part} failed on {result.get('worker')}: "
                                     f"{result['error']}; running it again\n")
                submit(part, avoid=result.get("worker"))
                continue
            results.append(result)
            progress.update(stage, len(results), parts, started)
            following = schedule.next(part)
            if following is not None:
                submit(following)
    progress.finish(stage, parts, time.monotonic() - started)
    return results


def convert(options):
    """The whole conversion; returns the report (stage times, every task's summary)."""
    output = os.path.abspath(options.output.rstrip("/"))
    work_dir = os.path.abspath(options.work_dir or os.path.join(
        os.path.dirname(output), "." + os.path.basename(output) + ".work"))
    progress = Progress(options.quiet)
    started = time.monotonic()
    report = {"output": output, "work_dir": work_dir, "stages": [], "tasks": []}
    client = None
    cluster = None
    try:
        plan = write_plan(options, work_dir)
        report["plan_seconds"] = time.monotonic() - started
        if options.scheduler:
            client = Client(options.scheduler)
        else:
            from distributed import LocalCluster
            cluster = LocalCluster(n_workers=options.local_workers, threads_per_worker=1,
                                   processes=True, dashboard_address=dashboard_address())
            client = Client(cluster)
        if not options.quiet and client.dashboard_link and dashboard_address() is not None:
            sys.stderr.write(f"Dask dashboard: {client.dashboard_link}\n")
        run_id = uuid.uuid4().hex[:8]
        placed = set()
        for stage in STAGES:
            stage_start = time.monotonic()
            if stage == "build":
                schedule = build_schedule(work_dir)
            elif stage == "place":
                # Only the parts their builds could not write in place.
                schedule = SubmitAll(part for part in range(stage_parts(stage, work_dir))
                                     if part not in placed)
            else:
                schedule = SubmitAll(range(stage_parts(stage, work_dir)))
            results = run_stage(client, options, plan, stage, schedule, progress, run_id)
            if stage == "build":
                placed = {result["part"] for result in results if result.get("placed")}
            report["stages"].append({"stage": stage, "tasks": len(results),
                                     "seconds": time.monotonic() - stage_start})
            report["tasks"] += results
            if stage == "build" and not options.keep_work:
                # The shards are read by the builds only: the disk they hold is free from here
                # (the work directory's peak is then two copies of the points, not three).
                shutil.rmtree(os.path.join(work_dir, "shards"), ignore_errors=True)
        report["seconds"] = time.monotonic() - started
        report["workers"] = len(client.scheduler_info()["workers"])
    except BaseException:
        if not options.keep_work:
            shutil.rmtree(work_dir, ignore_errors=True)
        raise
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    if not options.keep_work:
        shutil.rmtree(work_dir, ignore_errors=True)
    return report


def dashboard_address():
    """Dask's dashboard needs bokeh (not packaged by Debian 12): on where it is installed."""
    return ":0" if importlib.util.find_spec("bokeh") is not None else None
