"""/api/jobs: submit, show, list, cancel, images, and the WebSocket tile stream."""

import io
import json
import time
import zipfile

import numpy as np
import pytest
import rtcore
from PIL import Image
from google.protobuf import json_format
from app.services import layer_files
from rt import job_pb2

from stream_reader import assemble, read_stream, wait_for


def submit(client, scene_id, width=96, height=72, **extra):
    body = {"scene_id": scene_id, "settings": {"width": width, "height": height}, **extra}
    response = client.post("/api/jobs", json=body)
    assert response.status_code == 202, response.text
    return response


def test_a_minimal_job_renders_and_its_stream_equals_image_png(client, cornell_id):
    response = submit(client, cornell_id, 300, 240, interactive=True)
    job = response.json()
    assert response.headers["location"] == f"/api/jobs/{job['id']}"
    assert job["state"] in ("QUEUED", "RUNNING")
    assert job["request"]["settings"]["max_depth"] == 5, "defaults are filled in"
    messages = read_stream(client, job["id"])
    tiles = [m for m in messages if m.WhichOneof("message") == "tile"]
    started = [m.started for m in messages if m.WhichOneof("message") == "started"]
    end = messages[-1]
    assert end.WhichOneof("message") == "end" and end.end.state == job_pb2.DONE
    done = client.get(f"/api/jobs/{job['id']}").json()
    assert done["state"] == "DONE" and done["progress"] == 1 and done["tiles_done"] == done["tiles_total"]
    assert done["passes"] == 2, "an interactive 300x240 job gets a preview pass"
    assert int(done["rays"]) > 300 * 240 and done["finished_at"] >= done["started_at"] > 0
    # Every tile exactly once per pass, covering the image.
    for pass_index in range(done["passes"]):
        rects = [(t.tile.region.x, t.tile.region.y) for t in tiles if getattr(t.tile.region, "pass") == pass_index]
        assert len(rects) == len(set(rects))
    assert len(tiles) == done["tiles_total"]
    # Workers announce tiles as they start them; an announcement never follows its tile.
    assert started, "no tile was announced as started"
    finished_at = {(getattr(m.tile.region, "pass"), m.tile.region.x, m.tile.region.y): i for i, m in enumerate(messages)
                   if m.WhichOneof("message") == "tile"}
    for i, m in enumerate(messages):
        if m.WhichOneof("message") == "started":
            assert finished_at[(getattr(m.started, "pass"), m.started.x, m.started.y)] > i
    png = client.get(f"/api/jobs/{job['id']}/image.png")
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    expected = np.asarray(Image.open(io.BytesIO(png.content)).convert("RGBA"))
    assert np.array_equal(assemble(tiles, 300, 240), expected)
    assert expected[..., :3].max() > 40, "the lit box is not black"


def test_exr_holds_linear_colour(client, cornell_id):
    job = submit(client, cornell_id).json()
    wait_for(client, job["id"])
    exr = client.get(f"/api/jobs/{job['id']}/image.exr")
    assert exr.status_code == 200 and exr.content[:4] == b"\x76\x2f\x31\x01"


def test_a_job_is_done_once_its_layers_are_saved_and_images_are_made_when_asked(client, cornell_id):
    job = submit(client, cornell_id).json()
    wait_for(client, job["id"])
    folder = client.app.state.settings.jobs_dir / job["id"]
    assert sorted(p.name for p in folder.iterdir()) == ["layers"]
    assert sorted(p.name for p in (folder / "layers").iterdir()) == ["color.npy", "layout.json"]
    color = layer_files.load(folder, "color")
    first = client.get(f"/api/jobs/{job['id']}/image.png").content
    assert (folder / "image.png").is_file() and not (folder / "image.exr").exists()
    assert client.get(f"/api/jobs/{job['id']}/image.png").content == first, "kept, not made again"
    # The PNG is the saved linear colour, encoded by the renderer's own function.
    expected = rtcore.encode_srgb8(np.ascontiguousarray(color))[..., :3]
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(first)).convert("RGB")), expected)
    assert client.get(f"/api/jobs/{job['id']}/image.exr").status_code == 200
    assert sorted(p.name for p in folder.iterdir()) == ["image.exr", "image.png", "layers"]


def test_bloom_is_one_last_tile_over_the_whole_image_and_moves_light_without_adding_any(client, cornell_id):
    settings = {"width": 96, "height": 72, "samples_per_pixel": 4, "exposure": 0.5, "tone_map": "REINHARD"}
    plain = submit(client, cornell_id, settings=settings).json()
    bloomed = submit(client, cornell_id, settings={**settings, "bloom_strength": 0.8, "bloom_threshold": 0.2}).json()
    messages = read_stream(client, bloomed["id"])
    done = wait_for(client, bloomed["id"])
    assert done["state"] == "DONE" and done["passes"] == 2 and done["tiles_done"] == done["tiles_total"]
    tiles = [m for m in messages if m.WhichOneof("message") == "tile"]
    last = tiles[-1].tile.region
    assert (getattr(last, "pass"), last.x, last.y, last.w, last.h) == (1, 0, 0, 96, 72)
    png = np.asarray(Image.open(io.BytesIO(client.get(f"/api/jobs/{bloomed['id']}/image.png").content)).convert("RGBA"))
    assert np.array_equal(assemble(tiles, 96, 72), png), "the stream ends with image.png, bloom included"
    wait_for(client, plain["id"])
    layers = {}
    for job in (plain, bloomed):
        layers[job["id"]] = layer_files.load(client.app.state.settings.jobs_dir / job["id"], "color").astype(np.float64)
    before, after = layers[plain["id"]], layers[bloomed["id"]]
    assert np.abs(after - before).max() > 0.01, "bloom changed the image"
    assert after.sum() == pytest.approx(before.sum(), rel=1e-5), "bloom moves light, it adds none"
    # Exposure and tone map shape the 8-bit image only: the tiles were encoded with them.
    encoded = rtcore.encode_srgb8(layers[bloomed["id"]].astype(np.float32), json.dumps(settings))
    assert np.array_equal(png, encoded)


def test_aux_outputs_are_images_and_exr_layers(client, cornell_id):
    job = submit(client, cornell_id, outputs=["DEPTH", "NORMAL", "ALBEDO", "BVH_COST"]).json()
    assert wait_for(client, job["id"])["state"] == "DONE"
    for name in ("depth", "normal", "albedo", "bvh_cost"):
        response = client.get(f"/api/jobs/{job['id']}/{name}.png")
        assert response.status_code == 200, name
        pixels = np.asarray(Image.open(io.BytesIO(response.content)))
        assert pixels.shape[:2] == (72, 96) and pixels.std() > 0, name
    exr = client.get(f"/api/jobs/{job['id']}/image.exr").content
    for channel in (b"depth", b"normal", b"albedo", b"bvh_cost"):
        assert channel in exr[:4096], channel
    plain = submit(client, cornell_id).json()
    wait_for(client, plain["id"])
    missing = client.get(f"/api/jobs/{plain['id']}/depth.png")
    assert missing.status_code == 404 and "outputs" in missing.json()["detail"]


@pytest.mark.parametrize("body, status, words", [
    ({"scene_id": "nope"}, 404, "nope"),
    ({"scene_id": "{cornell}", "settings": {"width": 0}}, 422, "settings.width: 0 is below the minimum 1"),
    ({"scene_id": "{cornell}", "settings": {"width": 16384, "height": 16384}}, 422, "limit"),
    ({"scene_id": "{cornell}", "settings": {"maxDepth": -1}}, 422, "settings.max_depth): invalid value -1"),
    ({"scene_id": "{cornell}", "settings": {"widht": 5}}, 422, "widht"),
    ({"scene_id": "{cornell}", "camera": {"position": [0, 0]}}, 422, "position: needs 3 values"),
    ({"scene_id": "{cornell}", "camera": {"position": [1, 1, 1], "target": [1, 1, 1]}}, 422, "must differ"),
    ({"scene_id": "{cornell}", "outputs": ["SPARKLES"]}, 422, "SPARKLES"),
])
def test_bad_job_requests_are_refused_naming_the_problem(client, cornell_id, body, status, words):
    if body.get("scene_id") == "{cornell}":
        body = {**body, "scene_id": cornell_id}
    response = client.post("/api/jobs", json=body)
    assert response.status_code == status, response.text
    assert words in response.json()["detail"]


def test_malformed_json_is_a_422(client):
    for content in (b"", b"{", b"[1, 2]", b"\xff\xfe"):
        response = client.post("/api/jobs", content=content, headers={"content-type": "application/json"})
        assert response.status_code == 422, content


def test_unknown_jobs_are_404(client):
    for url in ("/api/jobs/nope", "/api/jobs/nope/image.png", "/api/jobs/nope/image.exr"):
        assert client.get(url).status_code == 404
    assert client.delete("/api/jobs/nope").status_code == 404
    assert client.get("/api/jobs/nope/sparkles.png").status_code == 404


def test_jobs_are_listed_newest_first_and_paged(client, cornell_id):
    ids = [submit(client, cornell_id, 16, 16).json()["id"] for _ in range(3)]
    for job_id in ids:
        wait_for(client, job_id)
    first = client.get("/api/jobs?limit=2").json()
    assert [j["id"] for j in first["jobs"]] == ids[::-1][:2] and first["total"] >= 3
    second = client.get("/api/jobs?limit=2&offset=2").json()
    assert second["jobs"][0]["id"] == ids[0] and second["offset"] == 2
    assert client.get("/api/jobs?limit=0").status_code == 422


def test_cancel_stops_a_running_job_within_a_second(client, dragon_id):
    job = submit(client, dragon_id, 1024, 1024, settings={"width": 1024, "height": 1024, "lightSamples": 64}).json()
    deadline = time.monotonic() + 20
    while client.get(f"/api/jobs/{job['id']}").json()["tiles_done"] < 2:
        assert time.monotonic() < deadline, "no tile finished"
        time.sleep(0.05)
    started = time.monotonic()
    cancelled = client.delete(f"/api/jobs/{job['id']}").json()
    assert time.monotonic() - started < 1.0
    assert cancelled["state"] == "CANCELLED" and "cancel" in cancelled["error"]
    after = client.get(f"/api/jobs/{job['id']}").json()
    time.sleep(0.5)
    assert client.get(f"/api/jobs/{job['id']}").json()["tiles_done"] == after["tiles_done"]
    assert client.get(f"/api/jobs/{job['id']}/image.png").status_code == 409
    refused = client.get(f"/api/jobs/{job['id']}/layers/color")
    assert refused.status_code == 409 and "cancelled" in refused.json()["detail"]
    assert read_stream(client, job["id"])[-1].end.state == job_pb2.CANCELLED


def test_cancel_stops_the_tiles_already_rendering(client, dragon_id):
    # The preview of a 1024x1024 image at 2048 samples traces 128 x 128 pixels
    # at 2048 samples each: many seconds of both cores, unless cancel stops it.
    slow = {"width": 1024, "height": 1024, "samplesPerPixel": 2048}
    job = submit(client, dragon_id, settings=slow).json()
    with client.websocket_connect(f"/api/jobs/{job['id']}/tiles") as ws:
        first = job_pb2.TileStreamMessage.FromString(ws.receive_bytes())
    assert first.WhichOneof("message") == "started", "the preview tile is rendering"
    assert client.delete(f"/api/jobs/{job['id']}").json()["state"] == "CANCELLED"
    cancelled = time.monotonic()
    # The next job's tiles share the render pool, oldest tile first: they would
    # wait for the whole preview if it went on.
    small = submit(client, dragon_id, 64, 48).json()
    assert wait_for(client, small["id"], timeout=60)["state"] == "DONE"
    assert time.monotonic() - cancelled < 3, "the cancelled job's tile went on rendering"


def test_a_late_viewer_gets_the_image_so_far_then_the_rest(client, cornell_id):
    job = submit(client, cornell_id, 200, 150).json()
    early = read_stream(client, job["id"])
    late = read_stream(client, job["id"])  # after the end: the kept stream replays
    # Records aside: of those, a late viewer gets the latest only (test_job_stream_records.py).
    tiles = lambda messages: [m.SerializeToString() for m in messages if m.WhichOneof("message") != "job"]
    assert tiles(early) == tiles(late)


def test_unknown_job_stream_is_closed_with_a_reason(client):
    from starlette.websockets import WebSocketDisconnect

    with client.websocket_connect("/api/jobs/nope/tiles") as ws:
        with pytest.raises(WebSocketDisconnect) as closed:
            ws.receive_bytes()
    assert closed.value.code == 4404


def test_the_heat_map_legend_is_the_ramp_of_bvh_cost_png(client):
    response = client.get("/api/jobs/legends/bvh_cost.png")
    assert response.status_code == 200 and response.headers["content-type"] == "image/png"
    ramp = np.asarray(Image.open(io.BytesIO(response.content)).convert("RGB"))[0]
    assert tuple(ramp[0]) == (0, 0, 0) and tuple(ramp[-1]) == (255, 255, 255)
    brightness = ramp.astype(int).sum(axis=1)
    assert (np.diff(brightness) >= -2).all(), "the ramp brightens from low to high cost"


def test_adaptive_jobs_report_their_mean_samples_per_pixel(client, cornell_id):
    settings = {"width": 48, "height": 36, "samples_per_pixel": 64}
    uniform = wait_for(client, submit(client, cornell_id, settings=settings).json()["id"])
    assert uniform["mean_samples_per_pixel"] == 64
    adaptive = wait_for(client, submit(client, cornell_id, settings={**settings, "adaptive_threshold": 0.2}).json()["id"])
    assert adaptive["state"] == "DONE" and 0 < adaptive["mean_samples_per_pixel"] < 64


def test_pixels_the_preview_traced_are_not_traced_again(client, cornell_id, scenes_dir):
    """An interactive 320x240 job has a preview pass; the full-resolution
    tiles take its pixels: the job traces exactly the rays of one render of
    the image, and its image (colour and auxiliary layers) is that render's."""
    settings = {"width": 320, "height": 240, "samples_per_pixel": 4, "adaptive_threshold": 0.05}
    job = wait_for(client, submit(client, cornell_id, settings=settings, outputs=["DEPTH", "BVH_COST"],
                                  interactive=True).json()["id"])
    assert job["state"] == "DONE" and job["passes"] == 2
    # The embedded cluster's worker sees the data folder: it wrote every full-resolution tile there.
    assert job["tiles_via_shared_folder"] == job["tiles_total"] - 1 and job["tiles_via_network"] == 0
    scene = rtcore.Scene.load(str(scenes_dir / "cornell.obj"))
    request = job_pb2.JobRequest()
    json_format.ParseDict(job["request"], request)
    reference = scene.render_tile(request.camera.SerializeToString(), request.settings.SerializeToString(),
                                  0, 0, 320, 240, aux=["depth", "bvh_cost"])
    assert int(job["rays"]) == reference["rays"]
    assert job["mean_samples_per_pixel"] == pytest.approx(reference["samples"] / (320 * 240), rel=1e-6)
    folder = client.app.state.settings.jobs_dir / job["id"]
    for name in ("color", "depth", "bvh_cost"):
        saved = layer_files.load(folder, name)
        np.testing.assert_array_equal(saved.reshape(reference[name].shape), reference[name], err_msg=name)


def test_settings_the_renderer_refuses_are_refused_before_queueing(client, cornell_id):
    response = client.post("/api/jobs", json={"scene_id": cornell_id, "settings": {
        "pixel_filter": "GRID", "samples_per_pixel": 5}})
    assert response.status_code == 422 and "GRID takes a square number" in response.json()["detail"]


def test_settings_under_which_glass_would_never_finish_are_refused(client):
    # A glass pane (MTL dissolve 0.1: transmission 0.9) splits every ray it meets in two.
    obj = b"mtllib glass.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glass\nf 1 2 3\n"
    mtl = b"newmtl glass\nKd 0 0 0\nNi 1.5\nd 0.1\nillum 7\n"
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        z.writestr("pane.obj", obj)
        z.writestr("glass.mtl", mtl)
    scene = client.post("/api/scenes", files={"file": ("pane.zip", out.getvalue())})
    assert scene.status_code == 201, scene.text
    response = client.post("/api/jobs", json={"scene_id": scene.json()["id"], "settings": {
        "width": 8, "height": 8, "max_depth": 64, "min_contribution": 0}})
    assert response.status_code == 422
    detail = response.json()["detail"]
    assert "settings.max_depth: 64 with settings.min_contribution 0" in detail and "lower max_depth" in detail
    ok = client.post("/api/jobs", json={"scene_id": scene.json()["id"], "settings": {
        "width": 8, "height": 8, "max_depth": 64}})
    assert ok.status_code == 202, ok.text
