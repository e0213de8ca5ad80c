"""python -m app (with server/ on the path): serves the job service on HOST:PORT."""

import uvicorn

from .core.config import load_settings

if __name__ == "__main__":
    settings = load_settings()
    # No permessage-deflate: compressing every tile's pixels on the event loop
    # took more of a core than assembling the image (the stream is binary
    # pixels that rarely leave a LAN).
    # A stop signal ends the server within seconds even while viewers keep tile
    # streams open (uvicorn otherwise waits for every connection to close).
    uvicorn.run("app.main:app", host=settings.host, port=settings.port, log_level="info",
                ws_per_message_deflate=False, timeout_graceful_shutdown=5)
