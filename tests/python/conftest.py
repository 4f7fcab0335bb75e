"""Fixtures of the Python module's tests (test_module_*.py): the `parallax` executable, whose
output is the oracle, the shared test data, and small files Parallax generates.

Run by ctest (tests/python/CMakeLists.txt) with PYTHONPATH=<build>/python. A skipped test fails
the run: nothing here may pass by not running."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "net"))
from loopback_nginx import start_nginx  # noqa: E402

_skipped = []


def pytest_runtest_logreport(report):
    if report.skipped:
        _skipped.append(report.nodeid)


def pytest_sessionfinish(session, exitstatus):
    if _skipped and session.exitstatus == 0:
        print("\nskipped tests count as failures here: " + ", ".join(_skipped))
        session.exitstatus = 1


def _required_env(name):
    value = os.environ.get(name)
    if not value:
        raise RuntimeError(f"{name} is not set: run these tests through ctest")
    return value


@pytest.fixture(scope="session")
def cli():
    """Runs `parallax ARGS...` and returns its stdout; a failure raises with its stderr."""
    executable = _required_env("PARALLAX_EXECUTABLE")

    def run(*args):
        done = subprocess.run([executable, *map(str, args)], capture_output=True, text=True)
        if done.returncode != 0:
            raise AssertionError(f"parallax {' '.join(map(str, args))}: {done.stderr}")
        return done.stdout

    return run


@pytest.fixture(scope="session")
def data_dir():
    path = Path(_required_env("PARALLAX_TEST_DATA"))
    assert (path / "laz").is_dir(), f"{path} has no laz/ folder (see tests/CMakeLists.txt)"
    return path


@pytest.fixture(scope="session")
def generated(tmp_path_factory, cli):
    """Small files Parallax writes itself: generated scans in every PLY encoding, and LAS."""
    folder = tmp_path_factory.mktemp("generated")
    files = {}
    for encoding in ("binary", "ascii", "binary-be"):
        path = folder / f"scan-{encoding}.ply"
        cli("generate", "-o", path, "--points", 3000, "--format", encoding, "--seed", 7, "-q")
        files[f"ply-{encoding}"] = path
    files["las"] = folder / "scan.las"
    cli("convert", files["ply-binary"], "-o", files["las"], "-q")
    files["pcd"] = folder / "scan.pcd"
    cli("convert", files["ply-binary"], "-o", files["pcd"], "-q")
    return files


def cli_text(cli, path, out_dir):
    """The points of `path` as `parallax convert PATH -o OUT.txt` writes them: a dict of columns
    (float64), in the file's column order."""
    out = Path(out_dir) / (Path(path).name + ".txt")
    cli("convert", path, "-o", out, "-q")
    with open(out) as text:
        names = text.readline().split()
    values = np.loadtxt(out, skiprows=1, ndmin=2)
    assert values.shape[1] == len(names)
    return {name: values[:, i] for i, name in enumerate(names)}


@pytest.fixture(scope="session")
def nginx(tmp_path_factory):
    """A real nginx on a free loopback port serving a folder (tests/net/loopback_nginx.py): yields
    (root folder, base URL, access log path). HTTP's range cache is off, so that what a read
    fetches is what the server sends. A missing nginx fails, never skips."""
    os.environ["PARALLAX_HTTP_CACHE_MB"] = "0"
    prefix = tmp_path_factory.mktemp("nginx")
    root = prefix / "root"
    root.mkdir()
    server, base = start_nginx(root, prefix, access_log=True)
    try:
        yield root, base, prefix / "access.log"
    finally:
        server.terminate()
        server.wait(timeout=10)
