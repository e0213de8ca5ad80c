"""python -m app (with server/ on the path): serves the job service on HOST:PORT."""

import uvicorn

from .core.config import load_settings

if __name__ == "__main__":
    settings = load_settings()
    uvicorn.run("app.main:app", host=settings.host, port=settings.port, log_level="info")
