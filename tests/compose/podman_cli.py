"""The podman command line the compose test drives: runc and cgroupfs, because
crun fails on these hosts' cgroups (v1, no systemd)."""

import subprocess

PODMAN = ("podman", "--runtime", "runc", "--cgroup-manager=cgroupfs")


def podman(*args: str, check: bool = True, timeout: float = 300, **kwargs) -> subprocess.CompletedProcess:
    result = subprocess.run([*PODMAN, *map(str, args)], capture_output=True, text=True, timeout=timeout, **kwargs)
    if check and result.returncode != 0:
        raise RuntimeError(f"podman {' '.join(map(str, args))} failed ({result.returncode}):\n{result.stderr[-4000:]}")
    return result


def image_exists(name: str) -> bool:
    return podman("image", "exists", name, check=False).returncode == 0
