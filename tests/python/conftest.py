"""Fixtures of the Python module's tests (test_module_*.py): the `parallax` executable, whose
output is the oracle, the shared test data, and small files Parallax generates.

Run by ctest (tests/python/CMakeLists.txt) with PYTHONPATH=<build>/python. A skipped test fails
the run: nothing here may pass by not running."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

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
    """A real nginx on a free loopback port serving a folder (as tests/net/loopback_servers.h
    starts it): yields (root folder, base URL, access log path). HTTP's range cache is off, so
    that what a read fetches is what the server sends. A missing nginx fails, never skips."""
    import shutil
    import socket
    import time

    program = shutil.which("nginx") or "/usr/sbin/nginx"
    assert Path(program).exists(), "nginx not found: install the Debian package 'nginx-light'"
    os.environ["PARALLAX_HTTP_CACHE_MB"] = "0"
    prefix = tmp_path_factory.mktemp("nginx")
    root = prefix / "root"
    root.mkdir()
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    d = str(prefix)
    (prefix / "nginx.conf").write_text(
        "daemon off;\nmaster_process off;\nworker_processes 1;\n"
        f"pid {d}/nginx.pid;\nerror_log {d}/error.log warn;\n"
        "events { worker_connections 256; }\n"
        "http {\n"
        "  log_format parallax '$request_method $uri $status $body_bytes_sent \"$http_range\"';\n"
        f"  access_log {d}/access.log parallax;\n"
        f"  client_body_temp_path {d}/client_body;\n  proxy_temp_path {d}/proxy;\n"
        f"  fastcgi_temp_path {d}/fastcgi;\n  uwsgi_temp_path {d}/uwsgi;\n  scgi_temp_path {d}/scgi;\n"
        "  default_type application/octet-stream;\n"
        f"  server {{\n    listen 127.0.0.1:{port};\n    root {root};\n  }}\n}}\n"
    )
    server = subprocess.Popen(
        [program, "-p", d, "-c", str(prefix / "nginx.conf")],
        stdout=subprocess.DEVNULL,
        stderr=open(prefix / "stderr.log", "w"),
    )
    try:
        for _ in range(100):
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert server.poll() is None, (prefix / "stderr.log").read_text()
                time.sleep(0.05)
        else:
            raise AssertionError("nginx did not accept connections within 5 s")
        yield root, f"http://127.0.0.1:{port}", prefix / "access.log"
    finally:
        server.terminate()
        server.wait(timeout=10)
