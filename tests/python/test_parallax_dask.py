"""The distributed octree build on a real Dask cluster on loopback.

A `dask scheduler` and two `dask worker` processes are started once for the cluster tests (ports
chosen by the scheduler, read back from its scheduler file), each in its own session so that the
whole process group goes at the end, whatever happened; each test waits for two live workers
first (the test that kills one starts its replacement). Outputs are compared byte for byte with
`parallax convert` on this machine. BuildOrderTest checks the driver's order of the builds alone,
without a cluster.

Environment: PARALLAX_EXECUTABLE (the built parallax), PARALLAX_TEST_TMP (a scratch folder);
PYTHONPATH holds python/ (the driver); the interpreter imports distributed.
"""

import filecmp
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

PARALLAX = os.environ["PARALLAX_EXECUTABLE"]
TMP_ROOT = os.environ.get("PARALLAX_TEST_TMP", tempfile.gettempdir())
# Every wait is bounded: a hung cluster fails the test instead of the suite's timeout.
STARTUP_SECONDS = 60
RUN_SECONDS = 300


def run_parallax(*args):
    subprocess.run([PARALLAX, *args, "-q"], check=True, timeout=RUN_SECONDS)


def same_tree(left, right):
    """The files of two directories, names and bytes."""
    names = sorted(os.listdir(left))
    if names != sorted(os.listdir(right)):
        return False
    return all(filecmp.cmp(os.path.join(left, n), os.path.join(right, n), shallow=False)
               for n in names)


class LoopbackCluster:
    """A scheduler and workers on 127.0.0.1, each its own process group."""

    def __init__(self, directory):
        self.directory = directory
        self.scheduler_file = os.path.join(directory, "scheduler.json")
        self.processes = []
        self.scheduler = self._start(
            [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
             "--port", "0", "--no-dashboard", "--scheduler-file", self.scheduler_file],
            "scheduler.log")
        deadline = time.monotonic() + STARTUP_SECONDS
        while not os.path.exists(self.scheduler_file):
            if time.monotonic() > deadline or self.scheduler.poll() is not None:
                raise RuntimeError("the scheduler did not start: " + self.log("scheduler.log"))
            time.sleep(0.1)
        with open(self.scheduler_file, encoding="utf-8") as info:
            self.address = json.load(info)["address"]

    def _start(self, command, log_name):
        log = open(os.path.join(self.directory, log_name), "wb")
        process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, start_new_session=True,
                                   cwd=self.directory)
        log.close()
        self.processes.append(process)
        return process

    def log(self, log_name):
        with open(os.path.join(self.directory, log_name), encoding="utf-8", errors="replace") as f:
            return f.read()[-4000:]

    def start_worker(self, name, env=None):
        # Without a nanny: the worker is the process a test kills, and nothing restarts it.
        return self._start([sys.executable, "-m", "distributed.cli.dask_worker", self.address,
                            "--nthreads", "1", "--no-nanny", "--no-dashboard", "--name", name,
                            "--host", "127.0.0.1",
                            "--local-directory", os.path.join(self.directory, name)],
                           f"worker-{name}.log")

    def wait_for_workers(self, count):
        from distributed import Client
        with Client(self.address, timeout=STARTUP_SECONDS) as client:
            client.wait_for_workers(count, timeout=STARTUP_SECONDS)

    def stop(self):
        for process in self.processes:
            if process.poll() is None:
                try:
                    os.killpg(process.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            process.wait(timeout=STARTUP_SECONDS)


class BuildOrderTest(unittest.TestCase):
    """The driver's order of the builds (no cluster): two lanes from the ends of octree.bin."""

    def test_two_workers_take_one_lane_each_and_each_goes_on_with_its_neighbour(self):
        from parallax_dask.driver import BuildFromBothEnds
        order = BuildFromBothEnds(groups=7, split=3)  # lower 0 1 2, upper 6 5 4 3
        self.assertEqual(order.first(2), [0, 6])
        self.assertEqual(order.next(6), 5)  # the upper lane finished first: it goes on
        self.assertEqual(order.next(0), 1)
        self.assertEqual(order.next(1), 2)
        self.assertEqual(order.next(2), 4)  # the lower lane is done: the upper lane's next
        self.assertEqual(order.next(5), 3)
        self.assertIsNone(order.next(4))
        self.assertIsNone(order.next(3))

    def test_more_workers_than_lanes_start_from_both_ends_in_turn(self):
        from parallax_dask.driver import BuildFromBothEnds
        order = BuildFromBothEnds(groups=5, split=2)
        self.assertEqual(order.first(8), [0, 4, 1, 3, 2])  # every group, none twice
        self.assertIsNone(order.next(0))
        one_side = BuildFromBothEnds(groups=3, split=3)  # one chunk side only
        self.assertEqual(one_side.first(2), [0, 1])
        self.assertEqual(one_side.next(0), 2)


class DistributedConvertTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        os.makedirs(TMP_ROOT, exist_ok=True)
        cls.data = tempfile.mkdtemp(prefix="data-", dir=TMP_ROOT)
        # A scanned scene as PLY and the same points as LAS: two inputs merged, both split into
        # ranges.
        cls.ply = os.path.join(cls.data, "scan.ply")
        cls.las = os.path.join(cls.data, "scan.las")
        run_parallax("generate", "-o", cls.ply, "--points", "150000", "--seed", "7")
        run_parallax("convert", cls.ply, "-o", cls.las)
        # The reference: the local build, same options (a small budget: several chunks).
        cls.local = os.path.join(cls.data, "local", "octree")
        run_parallax("convert", cls.ply, cls.las, "-o", cls.local, "--memory", "16")
        # One cluster for every case: a scheduler and two workers (each a Python process that
        # imports distributed) started once instead of once a case.
        cls.cluster = LoopbackCluster(tempfile.mkdtemp(prefix="cluster-", dir=TMP_ROOT))
        cls.addClassCleanup(shutil.rmtree, cls.cluster.directory, True)
        cls.addClassCleanup(cls.cluster.stop)
        cls.cluster.start_worker("a")
        cls.cluster.start_worker("b")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def setUp(self):
        self.directory = tempfile.mkdtemp(prefix="case-", dir=TMP_ROOT)
        self.addCleanup(shutil.rmtree, self.directory, True)
        self.cluster.wait_for_workers(2)

    def drive(self, inputs, output, *extra, parallax=PARALLAX):
        command = [sys.executable, "-m", "parallax_dask", *inputs, "-o", output, "--scheduler",
                   self.cluster.address, "--parallax", parallax, "--memory", "16", *extra]
        return subprocess.run(command, capture_output=True, text=True, timeout=RUN_SECONDS,
                              check=False)

    def assertIdenticalToLocal(self, output):
        self.assertTrue(os.path.isfile(os.path.join(output, "metadata.json")))
        self.assertTrue(same_tree(self.local, output),
                        f"{output} differs from the local build {self.local}")

    def test_output_is_byte_identical_to_the_local_build(self):
        # --tasks 1: one range per input (2); 7: 150 000-point inputs in ranges of about
        # 300 000 / 7 points, 3 each (6).
        for tasks, ranges in (("1", 2), ("7", 6)):
            with self.subTest(tasks=tasks):
                output = os.path.join(self.directory, "tasks" + tasks, "octree")
                report = os.path.join(self.directory, f"report{tasks}.json")
                done = self.drive([self.ply, self.las], output, "--tasks", tasks,
                                  "--report", report)
                self.assertEqual(done.returncode, 0, done.stderr)
                self.assertIdenticalToLocal(output)
                with open(report, encoding="utf-8") as f:
                    ran = json.load(f)["tasks"]
                # Both workers took tasks when there were several, and every range ran.
                if tasks == "7":
                    self.assertEqual(len({t["worker"] for t in ran}), 2)
                self.assertEqual(sum(t["stage"] == "scan" for t in ran), ranges)
                # The builds write into octree.bin from both ends: the first of each lane
                # always in place (nothing before it on its side), the rest in place when their
                # neighbour was done; only the others' parts are copied by the place stage.
                builds = {t["part"]: t["placed"] for t in ran if t["stage"] == "build"}
                self.assertTrue(builds[0] and builds[max(builds)], builds)
                self.assertEqual(sorted(t["part"] for t in ran if t["stage"] == "place"),
                                 sorted(part for part, placed in builds.items() if not placed))
                # The work directory is gone; only the octree is left.
                self.assertEqual(os.listdir(os.path.dirname(output)), ["octree"])

    def test_a_worker_killed_mid_run_is_replaced_and_the_output_is_identical(self):
        # A wrapper around parallax that holds the first distribute task of range 0 until the
        # test has killed the worker running it (it writes that worker's process id first).
        marker = os.path.join(self.directory, "held")
        wrapper = os.path.join(self.directory, "parallax-held.sh")
        with open(wrapper, "w", encoding="utf-8") as script:
            script.write(f"""#!/bin/sh
if [ "$2" = distribute ] && [ "$5" = 0 ] && mkdir "{marker}" 2>/dev/null; then
  echo $PPID > "{marker}/worker.pid"
  sleep {RUN_SECONDS}
fi
exec "{PARALLAX}" "$@"
""")
        os.chmod(wrapper, 0o755)
        output = os.path.join(self.directory, "killed", "octree")
        driver = subprocess.Popen(
            [sys.executable, "-m", "parallax_dask", self.ply, self.las, "-o", output,
             "--scheduler", self.cluster.address, "--parallax", wrapper, "--memory", "16",
             "--tasks", "5"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
        self.addCleanup(lambda: driver.poll() is None and os.killpg(driver.pid, signal.SIGKILL))
        pid_file = os.path.join(marker, "worker.pid")
        deadline = time.monotonic() + RUN_SECONDS
        while not (os.path.exists(pid_file) and os.path.getsize(pid_file) > 0):
            self.assertIsNone(driver.poll(), "the driver ended before the held task ran")
            self.assertLess(time.monotonic(), deadline, "the held task never started")
            time.sleep(0.05)
        with open(pid_file, encoding="utf-8") as f:
            worker_pid = int(f.read())
        victim = next(p for p in self.cluster.processes if p.pid == worker_pid)
        self.assertFalse(os.path.exists(output), "the output exists before the run ended")
        os.killpg(victim.pid, signal.SIGKILL)  # the worker and the task it was running
        victim.wait(timeout=STARTUP_SECONDS)
        self.cluster.start_worker("c")  # its replacement
        stdout, stderr = driver.communicate(timeout=RUN_SECONDS)
        self.assertEqual(driver.returncode, 0, stderr)
        self.assertIdenticalToLocal(output)

    def test_a_failed_task_runs_again_on_the_other_worker(self):
        # A wrapper around parallax whose first build task of group 1 fails as an I/O error
        # would (exit status 1), once.
        marker = os.path.join(self.directory, "failed-once")
        wrapper = os.path.join(self.directory, "parallax-fails.sh")
        with open(wrapper, "w", encoding="utf-8") as script:
            script.write(f"""#!/bin/sh
if [ "$2" = build ] && [ "$5" = 1 ] && mkdir "{marker}" 2>/dev/null; then
  echo "parallax: error: simulated failure of a shared disk" >&2
  exit 1
fi
exec "{PARALLAX}" "$@"
""")
        os.chmod(wrapper, 0o755)
        output = os.path.join(self.directory, "retried", "octree")
        report = os.path.join(self.directory, "retried.json")
        done = self.drive([self.ply, self.las], output, "--tasks", "5", "--report", report,
                          parallax=wrapper)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertTrue(os.path.isdir(marker), "the failure was not simulated")
        # Said, with the worker it failed on; then run again on the other one.
        failed = re.search(r"build task 1 failed on (tcp://127\.0\.0\.1:\d+): exit status 1: "
                           r"parallax: error: simulated failure", done.stderr)
        self.assertIsNotNone(failed, done.stderr)
        with open(report, encoding="utf-8") as f:
            rerun = [t for t in json.load(f)["tasks"] if t["stage"] == "build" and t["part"] == 1]
        self.assertEqual(len(rerun), 1)
        self.assertNotEqual(rerun[0]["worker"], failed.group(1))
        self.assertIdenticalToLocal(output)

    def test_malformed_input_stops_the_run_with_its_error(self):
        # An ascii PLY whose 3rd vertex has a word where a number belongs: the header is fine
        # (the plan is made), the scan task of its range finds the value.
        bad = os.path.join(self.directory, "bad.ply")
        with open(bad, "w", encoding="utf-8") as f:
            f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n"
                    "0 0 0\n1 1 1\n2 abc 2\n3 3 3\n")
        output = os.path.join(self.directory, "bad", "octree")
        done = self.drive([self.ply, bad], output, "--tasks", "4")
        self.assertEqual(done.returncode, 2, done.stderr)
        self.assertIn("parallax_dask: error: ", done.stderr)
        self.assertIn(bad, done.stderr)
        self.assertIn("line 10", done.stderr)
        self.assertIn("abc", done.stderr)
        # Nothing that looks finished: no output, no work directory.
        self.assertEqual(os.listdir(os.path.dirname(output)) if os.path.isdir(
            os.path.dirname(output)) else [], [])


if __name__ == "__main__":
    unittest.main()
