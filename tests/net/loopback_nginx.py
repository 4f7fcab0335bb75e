"""A real nginx on a free loopback port serving a folder, for the Python module's tests
(tests/python/conftest.py) and scripts/bench_python_copc.py; tests/net/loopback_servers.h starts
the same server for the C++ tests."""

import shutil
import socket
import subprocess
import time
from pathlib import Path


def start_nginx(root, prefix, access_log=False):
    """Starts nginx serving `root`, its configuration, pid, logs and temporary folders in `prefix`
    (created when missing). With `access_log`, each request is logged to prefix/access.log as
    'METHOD URI STATUS BYTES "RANGE"'. Returns (process, base URL) once it accepts connections;
    raises RuntimeError with nginx's own stderr when it does not within 5 s."""
    program = shutil.which("nginx") or "/usr/sbin/nginx"
    if not Path(program).exists():
        raise RuntimeError("nginx not found: install the Debian package 'nginx'")
    prefix = Path(prefix)
    prefix.mkdir(parents=True, exist_ok=True)
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    d = str(prefix)
    log = (
        "  log_format parallax '$request_method $uri $status $body_bytes_sent \"$http_range\"';\n"
        f"  access_log {d}/access.log parallax;\n"
        if access_log
        else "  access_log off;\n"
    )
    (prefix / "nginx.conf").write_text(
        "daemon off;\nmaster_process off;\nworker_processes 1;\n"
        f"pid {d}/nginx.pid;\nerror_log {d}/error.log warn;\n"
        "events { worker_connections 256; }\n"
        "http {\n" + log +
        f"  client_body_temp_path {d}/client_body;\n  proxy_temp_path {d}/proxy;\n"
        f"  fastcgi_temp_path {d}/fastcgi;\n  uwsgi_temp_path {d}/uwsgi;\n  scgi_temp_path {d}/scgi;\n"
        "  default_type application/octet-stream;\n  keepalive_requests 100000;\n"
        f"  server {{\n    listen 127.0.0.1:{port};\n    root {root};\n  }}\n}}\n"
    )
    stderr_path = prefix / "stderr.log"
    with open(stderr_path, "w") as stderr:
        server = subprocess.Popen([program, "-p", d, "-c", str(prefix / "nginx.conf")],
                                  stdout=subprocess.DEVNULL, stderr=stderr)
    for _ in range(100):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return server, f"http://127.0.0.1:{port}"
        except OSError:
            if server.poll() is not None:
                break
            time.sleep(0.05)
    server.terminate()
    server.wait(timeout=10)
    raise RuntimeError(f"nginx did not accept connections within 5 s: {stderr_path.read_text()}")
