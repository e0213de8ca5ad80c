"""/api/jobs/{id}/compare/{reference}: one done job's image against another's,
measured as `make charts` measures them (renderer/bench/accuracy_measure.py,
imported here), over the whole image or a rectangle; the HDR-FLIP map."""

import sys
from pathlib import Path

import numpy as np
import pytest
from app.services import layer_files
from rt import job_pb2

from stream_reader import wait_for

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "renderer" / "bench"))
from accuracy_measure import mean_flip, rmse  # noqa: E402


def done_job(client, scene_id, width=48, height=36, spp=1):
    body = {"scene_id": scene_id, "settings": {"width": width, "height": height, "samples_per_pixel": spp}}
    job = client.post("/api/jobs", json=body).json()
    assert wait_for(client, job["id"])["state"] == "DONE"
    return job["id"]


@pytest.fixture(scope="module")
def pair(client, cornell_id):
    """A noisy job and a reference of the same view, and their linear colours."""
    noisy, reference = done_job(client, cornell_id, spp=1), done_job(client, cornell_id, spp=64)
    jobs_dir = client.app.state.settings.jobs_dir
    colours = {j: np.asarray(layer_files.load(jobs_dir / j, "color"), np.float32) for j in (noisy, reference)}
    return noisy, reference, colours


def test_the_metrics_are_make_charts_numbers(client, pair):
    noisy, reference, colours = pair
    response = client.get(f"/api/jobs/{noisy}/compare/{reference}")
    assert response.status_code == 200, response.text
    measured = response.json()
    assert (measured["x"], measured["y"], measured["w"], measured["h"]) == (0, 0, 48, 36)
    assert measured["rmse"] == pytest.approx(rmse(colours[reference], colours[noisy]), rel=1e-12)
    assert measured["mean_flip"] == pytest.approx(mean_flip(colours[reference], colours[noisy]), rel=1e-6)
    error = colours[noisy].astype(np.float64) - colours[reference]
    relative = np.mean(error ** 2 / (colours[reference].astype(np.float64) ** 2 + 0.01))
    assert measured["relative_mse"] == pytest.approx(relative, rel=1e-12)
    assert measured["rmse"] > 0.01 and measured["mean_flip"] > 0.01, "1 spp against 64 differs"


def test_a_job_against_itself_measures_zero(client, pair):
    noisy, _, _ = pair
    measured = client.get(f"/api/jobs/{noisy}/compare/{noisy}").json()
    assert measured["rmse"] == 0 and measured["relative_mse"] == 0 and measured["mean_flip"] == 0
    flip = job_pb2.Layer.FromString(client.get(f"/api/jobs/{noisy}/compare/{noisy}/flip").content)
    assert not np.frombuffer(flip.data, "<f4").any()


def test_a_rectangle_is_measured_on_its_pixels_and_the_whole_image_flip_map(client, pair):
    noisy, reference, colours = pair
    response = client.get(f"/api/jobs/{noisy}/compare/{reference}?x=10&y=4&w=20&h=12")
    assert response.status_code == 200, response.text
    measured = response.json()
    window = np.s_[4:16, 10:30]
    assert measured["rmse"] == pytest.approx(rmse(colours[reference][window], colours[noisy][window]), rel=1e-12)
    flip = job_pb2.Layer.FromString(client.get(f"/api/jobs/{noisy}/compare/{reference}/flip").content)
    assert list(flip.shape) == [36, 48, 1] and list(flip.channels) == ["flip"]
    error_map = np.frombuffer(flip.data, "<f4").reshape(36, 48)
    assert measured["mean_flip"] == pytest.approx(float(error_map[window].astype(np.float64).mean()), rel=1e-12)
    whole = client.get(f"/api/jobs/{noisy}/compare/{reference}").json()["mean_flip"]
    assert float(error_map.astype(np.float64).mean()) == pytest.approx(whole, rel=1e-4)


@pytest.mark.parametrize("query, words", [
    ("?x=40&y=0&w=20&h=10", "not inside the 48x36 image"),
    ("?x=0&y=0&w=10", "needs all of x, y, w and h"),
    ("?x=0&y=0&w=0&h=4", "w"),
])
def test_a_bad_rectangle_is_refused_in_words(client, pair, query, words):
    noisy, reference, _ = pair
    response = client.get(f"/api/jobs/{noisy}/compare/{reference}{query}")
    assert response.status_code == 422 and words in response.text, response.text


def test_images_of_other_sizes_or_unknown_jobs_are_refused(client, cornell_id, pair):
    noisy, _, _ = pair
    other = done_job(client, cornell_id, width=40, height=30)
    response = client.get(f"/api/jobs/{noisy}/compare/{other}")
    assert response.status_code == 422 and "48x36" in response.text and "40x30" in response.text
    assert client.get(f"/api/jobs/{noisy}/compare/{other}/flip").status_code == 422
    missing = client.get(f"/api/jobs/{noisy}/compare/nojob")
    assert missing.status_code == 404 and "nojob" in missing.text
