"""The peak resident memory of the running process, as the bench peers (icp_open3d.py,
normals_open3d.py) report it in their JSON line for `parallax bench ... --peer`."""


def peak_kb():
    """VmHWM of /proc/self/status in kB (None where the kernel does not report it)."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    return None
