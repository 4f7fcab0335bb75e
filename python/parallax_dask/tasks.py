"""What a Dask worker runs: one `parallax convert-task` process.

The function is sent to the workers by value (see driver.py), so a worker needs Dask and the
parallax executable, not this package.
"""

import json
import socket
import subprocess
import time

# `parallax` exits with 2 for bad input (an InputError: the file, where in it, what was
# expected); running such a task again gives the same error, so it is not retried.
INPUT_ERROR_STATUS = 2


def run_convert_task(parallax, stage, plan, part, threads):
    """Runs one task; returns a dict that says how it went (never raises for a failed task).

    ok: the task's own summary (stage, part, points, seconds) with the wall time of the process
    and the host that ran it. Failed: "input_error" (bad input, final) or "error" (anything
    else: the driver runs it again, elsewhere when it can), with the task's stderr.
    """
    command = [parallax, "convert-task", stage, plan, "--part", str(part),
               "--threads", str(threads)]
    start = time.monotonic()
    worker = None
    try:
        from distributed import get_worker  # on a worker; the driver may call it directly too
        worker = get_worker().address
    except (ImportError, ValueError):
        pass
    try:
        done = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as error:
        return {"stage": stage, "part": part, "host": socket.gethostname(), "worker": worker,
                "error": f"cannot run {parallax}: {error}"}
    result = {"stage": stage, "part": part, "host": socket.gethostname(), "worker": worker,
              "wall_seconds": time.monotonic() - start}
    stderr = done.stderr.strip()
    if done.returncode == 0:
        lines = done.stdout.strip().splitlines()
        try:
            result.update(json.loads(lines[-1]))
        except (IndexError, ValueError):
            result["error"] = f"no summary on stdout: {done.stdout!r}"
        return result
    if done.returncode == INPUT_ERROR_STATUS:
        result["input_error"] = stderr
    else:
        result["error"] = f"exit status {done.returncode}: {stderr}"
    return result
