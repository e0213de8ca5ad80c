"""Reading a job's tile stream the way the viewer does."""

import time

import numpy as np
from rt import job_pb2


def read_stream(client, job_id: str) -> list[job_pb2.TileStreamMessage]:
    """Every message of the job's WebSocket until the server closes it."""
    from starlette.websockets import WebSocketDisconnect

    messages = []
    with client.websocket_connect(f"/api/jobs/{job_id}/tiles") as ws:
        try:
            while True:
                message = job_pb2.TileStreamMessage.FromString(ws.receive_bytes())
                messages.append(message)
                if message.WhichOneof("message") == "end":
                    break
        except WebSocketDisconnect:
            pass
    return messages


def assemble(messages, width: int, height: int) -> np.ndarray:
    """Paints tiles in arrival order, previews over their blocks, as the viewer does."""
    canvas = np.zeros((height, width, 4), np.uint8)
    for message in messages:
        if message.WhichOneof("message") != "tile":
            continue
        t, s = message.tile.region, message.tile.scale
        samples = np.frombuffer(message.tile.pixels, np.uint8).reshape(-(-t.h // s), -(-t.w // s), 4)
        block = np.repeat(np.repeat(samples, s, axis=0), s, axis=1)[:t.h, :t.w]
        canvas[t.y:t.y + t.h, t.x:t.x + t.w] = block
    return canvas


def wait_for(client, job_id: str, timeout: float = 60, headers: dict | None = None) -> dict:
    """The job's record once it has ended (`headers`: a named user's token)."""
    deadline = time.monotonic() + timeout
    while True:
        job = client.get(f"/api/jobs/{job_id}", headers=headers).json()
        if job["state"] in ("DONE", "FAILED", "CANCELLED"):
            return job
        assert time.monotonic() < deadline, f"job {job_id} still {job['state']}"
        time.sleep(0.05)


def render_color(client, body: dict) -> tuple[dict, np.ndarray]:
    """Submits the job `body`, waits for it to be DONE, and returns its record and colour (RGB)."""
    from app.services import layer_files

    response = client.post("/api/jobs", json=body)
    assert response.status_code == 202, response.text
    job = wait_for(client, response.json()["id"])
    assert job["state"] == "DONE", job
    return job, layer_files.load(client.app.state.settings.jobs_dir / job["id"], "color")[..., :3]
