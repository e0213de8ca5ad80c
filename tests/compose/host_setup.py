"""What a fresh Debian host needs before it can build and run the image with
podman: the packages (when missing) and one containers.conf setting."""

import os
import re
import shutil
import subprocess
from pathlib import Path

# qemu-user runs the image's renderer on an emulated CPU.
PACKAGES = ("podman", "runc", "debootstrap", "qemu-user", "ca-certificates")
CONTAINERS_CONF = Path("/etc/containers/containers.conf")


def missing_packages(packages=PACKAGES) -> list[str]:
    def installed(package):
        status = subprocess.run(["dpkg-query", "-W", "-f=${Status}", package], capture_output=True, text=True)
        return status.stdout.endswith("ok installed")
    return [p for p in packages if not installed(p)]


def install_packages() -> None:
    missing = missing_packages()
    if not missing:
        return
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    subprocess.run(["apt-get", "update", "-qq"], check=True, env=env)
    subprocess.run(["apt-get", "install", "-y", "-qq", *missing], check=True, env=env, stdout=subprocess.DEVNULL)


def allow_inherited_ulimits(conf: Path = CONTAINERS_CONF) -> None:
    """podman raises a container's open-file limit to 1048576 by default, which
    these hosts forbid (runc: "error setting rlimits ... operation not
    permitted"); `default_ulimits = []` keeps the host's limits."""
    text = conf.read_text() if conf.exists() else ""
    if re.search(r"^\s*default_ulimits\s*=", text, re.M):
        return
    if re.search(r"^\[containers\]\s*$", text, re.M):
        text = re.sub(r"^\[containers\]\s*$", "[containers]\ndefault_ulimits = []", text, count=1, flags=re.M)
    else:
        text = text + ("\n" if text and not text.endswith("\n") else "") + "[containers]\ndefault_ulimits = []\n"
    conf.parent.mkdir(parents=True, exist_ok=True)
    conf.write_text(text)


def prepare_host() -> None:
    if os.geteuid() != 0:
        raise RuntimeError("the compose test installs packages and runs rootful podman: run it as root")
    install_packages()
    allow_inherited_ulimits()
    assert shutil.which("podman"), "podman is missing after installing it"
