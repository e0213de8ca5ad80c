"""Settings for a service under test: its own data folder, no viewer unless given one."""

from pathlib import Path

from app.core.config import Settings


def service_settings(data_dir: Path, **overrides) -> Settings:
    # "testserver": the Host header of Starlette's TestClient.
    return Settings(**{"data_dir": data_dir, "embedded_threads": 2, "web_dir": data_dir / "no-viewer",
                       "allowed_hosts": ("testserver",), **overrides})
