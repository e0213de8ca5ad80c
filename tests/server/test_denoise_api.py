"""settings.denoise through the job service: the last pass denoises the
colour with the albedo and normal layers as guides and keeps the image before
denoising as the "noisy" layer, which every image route serves and the
compare route measures."""

import io

import numpy as np
import rtcore
from PIL import Image
from app.services import layer_files
from rt import job_pb2

from stream_reader import wait_for

SETTINGS = {"width": 48, "height": 36, "samples_per_pixel": 4, "light_samples": 2}


def submit(client, scene_id: str, **settings) -> dict:
    response = client.post("/api/jobs", json={"scene_id": scene_id, "settings": {**SETTINGS, **settings}})
    assert response.status_code == 202, response.text
    job = wait_for(client, response.json()["id"])
    assert job["state"] == "DONE", job
    return job


def layer(client, job_id: str, name: str) -> np.ndarray:
    response = client.get(f"/api/jobs/{job_id}/layers/{name}")
    assert response.status_code == 200, response.text
    message = job_pb2.Layer.FromString(response.content)
    return np.frombuffer(message.data, "<f4").reshape(tuple(message.shape))


def test_a_denoised_job_keeps_its_noisy_image_byte_for_byte(client, cornell_id):
    plain = submit(client, cornell_id)
    denoised = submit(client, cornell_id, denoise="OIDN")
    assert denoised["request"]["settings"]["denoise"] == "OIDN"
    assert denoised["passes"] == plain["passes"] + 1 and denoised["denoise_seconds"] > 0
    assert plain["denoise_seconds"] == 0
    noisy = layer(client, denoised["id"], "noisy")
    # The denoiser's guides change nothing in the render: the job without it is the same image.
    assert noisy.tobytes() == layer(client, plain["id"], "color").tobytes()
    color, albedo, normal = (np.ascontiguousarray(layer(client, denoised["id"], n)) for n in ("color", "albedo", "normal"))
    assert not np.array_equal(color, noisy)
    # Deterministic: denoising the same layers again gives the job's colour bit for bit.
    assert np.array_equal(color, rtcore.denoise(np.ascontiguousarray(noisy), albedo, normal))
    # The guides were rendered, though nobody asked for them as outputs.
    assert albedo.max() > 0.1 and np.abs(np.linalg.norm(normal, axis=2) - 1).min() < 1e-3


def test_the_noisy_image_is_served_and_compared(client, cornell_id):
    job = submit(client, cornell_id, denoise="OIDN")
    png = client.get(f"/api/jobs/{job['id']}/noisy.png")
    assert png.status_code == 200
    noisy = layer(client, job["id"], "noisy")
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(png.content)).convert("RGBA")),
                          rtcore.encode_srgb8(np.ascontiguousarray(noisy), None))
    exr = client.get(f"/api/jobs/{job['id']}/image.exr")
    assert exr.status_code == 200
    for channel in (b"noisy.R", b"noisy.G", b"noisy.B", b"albedo.R", b"normal.X"):
        assert channel + b"\0" in exr.content[:2000]

    itself = client.get(f"/api/jobs/{job['id']}/compare/{job['id']}", params={"layer": "noisy",
                                                                              "reference_layer": "noisy"}).json()
    assert itself["layer"] == itself["reference_layer"] == "noisy"
    assert itself["rmse"] == 0 and itself["mean_flip"] == 0
    pair = client.get(f"/api/jobs/{job['id']}/compare/{job['id']}", params={"layer": "noisy"}).json()
    color = layer(client, job["id"], "color").astype(np.float64)
    assert pair["layer"] == "noisy" and pair["reference_layer"] == "color"
    assert np.isclose(pair["rmse"], np.sqrt(np.mean((noisy - color) ** 2)))
    flip = client.get(f"/api/jobs/{job['id']}/compare/{job['id']}/flip", params={"layer": "noisy"})
    values = np.frombuffer(job_pb2.Layer.FromString(flip.content).data, "<f4")
    assert np.isclose(values.mean(), pair["mean_flip"], rtol=1e-5)


def test_a_job_without_denoising_has_no_noisy_image(client, cornell_id):
    job = submit(client, cornell_id)
    missing = client.get(f"/api/jobs/{job['id']}/layers/noisy")
    assert missing.status_code == 404 and "settings.denoise" in missing.json()["detail"]
    assert client.get(f"/api/jobs/{job['id']}/noisy.png").status_code == 404
    compare = client.get(f"/api/jobs/{job['id']}/compare/{job['id']}", params={"layer": "noisy"})
    assert compare.status_code == 404 and "no noisy layer" in compare.json()["detail"]
    wrong = client.get(f"/api/jobs/{job['id']}/compare/{job['id']}", params={"layer": "albedo"})
    assert wrong.status_code == 422
    assert not (client.app.state.settings.jobs_dir / job["id"] / layer_files.COMPLETE / "noisy.npy").exists()


def test_an_unknown_denoiser_is_refused_by_name(client, cornell_id):
    response = client.post("/api/jobs", json={"scene_id": cornell_id, "settings": {"denoise": "NEURAL"}})
    assert response.status_code in (400, 422) and "denoise" in response.text
