"""docker-compose.yml brought up with podman alone, read from the file users
get, so that the file is what the test proves.

podman-compose (Debian's 1.0.3) cannot: it takes the "CMD" off a health
check's list in place, so the second worker replica's check starts with
"python" and it stops ("unknown healthcheck test type"); it would also start a
service as soon as the one it depends on is created, ignoring `condition:
service_healthy`, and it quotes an exec-form check wrongly. And podman runs health
checks from systemd timers, which hosts without systemd (containers, CI) do not
have, so no check ever runs by itself. This runner does both itself: it starts
the services in dependency order, and runs each container's health check with
`podman healthcheck run` on the file's schedule (interval, start_period,
retries) until it passes, before starting what depends on it.

What it changes from the file, and why: published ports go to free loopback
ports (the file's 8000 and 8787 may be taken on a shared machine), and every
name is prefixed with the project's so that a run never meets another's."""

import json
import re
import time
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from podman_cli import podman

LABEL = "io.rt.compose-test.project"


def seconds(duration: str | int | float) -> float:
    """A compose duration ("1m30s", "10s", "500ms") in seconds."""
    if isinstance(duration, (int, float)):
        return float(duration)
    units = {"h": 3600, "m": 60, "s": 1, "ms": 0.001, "us": 1e-6}
    parts = re.findall(r"(\d+(?:\.\d+)?)(ms|us|h|m|s)", duration)
    if not parts or "".join(n + u for n, u in parts) != duration:
        raise ValueError(f"not a compose duration: {duration!r}")
    return sum(float(n) * units[u] for n, u in parts)


@dataclass
class Service:
    name: str
    spec: dict
    containers: list[str] = field(default_factory=list)

    @property
    def replicas(self) -> int:
        return int((self.spec.get("deploy") or {}).get("replicas", 1))

    @property
    def depends_on(self) -> dict[str, str]:
        """Each dependency and its condition (a list means service_started)."""
        deps = self.spec.get("depends_on") or {}
        if isinstance(deps, list):
            return {d: "service_started" for d in deps}
        return {d: (c or {}).get("condition", "service_started") for d, c in deps.items()}


class ComposeTopology:
    def __init__(self, compose_file: Path, project: str, logs: Path):
        self.compose = yaml.safe_load(compose_file.read_text())  # PyYAML resolves the `<<` merge keys
        self.project = project
        self.logs = logs
        self.network = f"{project}_default"
        self.services = {name: Service(name, spec) for name, spec in self.compose["services"].items()}

    def volume(self, name: str) -> str:
        return f"{self.project}_{name}"

    def start_order(self) -> list[Service]:
        order, seen = [], set()

        def visit(service: Service, path: tuple = ()):
            if service.name in path:
                raise ValueError(f"dependency cycle: {path + (service.name,)}")
            if service.name in seen:
                return
            for dep in service.depends_on:
                visit(self.services[dep], path + (service.name,))
            seen.add(service.name)
            order.append(service)

        for service in self.services.values():
            visit(service)
        return order

    def run_args(self, service: Service, container: str) -> list[str]:
        spec = service.spec
        args = ["run", "-d", "--name", container, "--label", f"{LABEL}={self.project}",
                "--network", self.network, "--network-alias", service.name]
        for volume in spec.get("volumes", []):
            source, target = volume.split(":", 1)
            args += ["-v", f"{self.volume(source) if source in (self.compose.get('volumes') or {}) else source}:{target}"]
        environment = spec.get("environment") or {}
        if isinstance(environment, list):
            environment = dict(item.split("=", 1) for item in environment)
        for key, value in environment.items():
            args += ["-e", f"{key}={value}"]
        for port in spec.get("ports", []):
            args += ["-p", f"127.0.0.1::{str(port).rsplit(':', 1)[-1]}"]
        check = spec.get("healthcheck")
        if check:
            test = check["test"]
            # podman 4.3 takes the exec form as a JSON array without its "CMD" (with it, it
            # stores the whole array as one word and the check always fails); CMD-SHELL and a
            # string go through a shell.
            command = json.dumps(test[1:]) if test[0] == "CMD" else (test[1] if isinstance(test, list) else test)
            args += ["--health-cmd", command,
                     "--health-interval", str(check.get("interval", "30s")),
                     "--health-timeout", str(check.get("timeout", "30s")),
                     "--health-retries", str(check.get("retries", 3)),
                     "--health-start-period", str(check.get("start_period", "0s"))]
        return [*args, spec["image"], *spec.get("command", [])]

    def up(self) -> None:
        self.down()  # what an interrupted earlier run left
        podman("network", "create", self.network)
        for name in self.compose.get("volumes") or {}:
            podman("volume", "create", self.volume(name))
        for service in self.start_order():
            for dep, condition in service.depends_on.items():
                if condition == "service_healthy":
                    for container in self.services[dep].containers:
                        self.wait_healthy(container, self.services[dep].spec["healthcheck"])
            for number in range(1, service.replicas + 1):
                container = f"{self.project}_{service.name}_{number}"
                podman(*self.run_args(service, container))
                service.containers.append(container)
        for service in self.services.values():
            if service.spec.get("healthcheck"):
                for container in service.containers:
                    self.wait_healthy(container, service.spec["healthcheck"])

    def wait_healthy(self, container: str, check: dict) -> None:
        """The engine's schedule: a check every interval; failures during
        start_period do not count, then `retries` failures in a row make it unhealthy."""
        interval, start = seconds(check.get("interval", "30s")), seconds(check.get("start_period", "0s"))
        retries, started, failures = int(check.get("retries", 3)), time.monotonic(), 0
        while True:
            result = podman("healthcheck", "run", container, check=False, timeout=seconds(check.get("timeout", "30s")) + 30)
            if result.returncode == 0:
                return
            if time.monotonic() - started > start:
                failures += 1
                if failures >= retries:
                    raise AssertionError(f"{container} is unhealthy ({result.stdout.strip()} {result.stderr.strip()})"
                                         f"; its log:\n{self.log(container)[-3000:]}")
            time.sleep(min(interval, 2.0) if time.monotonic() - started <= start else interval)

    def health(self, container: str) -> str:
        state = json.loads(podman("inspect", "--format", "{{json .State}}", container).stdout)
        return (state.get("Health") or state.get("Healthcheck") or {}).get("Status", "")

    def published(self, container: str, port: int) -> str:
        """host:port that a container's published port answers on."""
        return podman("port", container, f"{port}/tcp").stdout.strip().splitlines()[0]

    def log(self, container: str) -> str:
        result = podman("logs", container, check=False)
        return result.stdout + result.stderr

    def kill(self, container: str) -> None:
        podman("kill", container)

    def down(self) -> None:
        """Every container, the network and the volumes, whatever state they are in;
        each container's log is kept in `logs` first."""
        listed = podman("ps", "-a", "--filter", f"label={LABEL}={self.project}", "--format", "{{.Names}}", check=False)
        for container in listed.stdout.split():
            (self.logs / f"{container}.log").write_text(self.log(container))
            podman("rm", "-f", "-t", "5", container, check=False)
        podman("network", "rm", "-f", self.network, check=False)
        for name in self.compose.get("volumes") or {}:
            podman("volume", "rm", "-f", self.volume(name), check=False)
        for service in self.services.values():
            service.containers.clear()
