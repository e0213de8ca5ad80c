"""References: a done job marked as its view's reference (scene, camera and
size), the view's jobs measured against it as time and error, and a job
rendered as a reference marking itself once done."""

import json

import pytest

from stream_reader import wait_for

CAMERA = {"position": [0.1, 1.0, 3.2], "target": [0.0, 1.0, 0.0], "up": [0, 1, 0], "fov_y": 45}


def done_job(client, scene_id, spp=1, width=40, height=30, **extra):
    body = {"scene_id": scene_id, "camera": CAMERA,
            "settings": {"width": width, "height": height, "samples_per_pixel": spp}, **extra}
    response = client.post("/api/jobs", json=body)
    assert response.status_code == 202, response.text
    job = wait_for(client, response.json()["id"])
    assert job["state"] == "DONE"
    return job


@pytest.fixture(scope="module")
def view(client, cornell_id):
    """A reference of a view, two jobs of it and one of another size."""
    reference, a, b = done_job(client, cornell_id, 32), done_job(client, cornell_id, 1), done_job(client, cornell_id, 4)
    other_size = done_job(client, cornell_id, 1, width=32, height=24)
    response = client.put(f"/api/scenes/{cornell_id}/references/{reference['id']}")
    assert response.status_code == 200, response.text
    assert reference["id"] in response.json()["reference_jobs"]
    return reference, a, b, other_size


def test_the_views_jobs_are_points_of_time_against_error(client, cornell_id, view):
    reference, a, b, other_size = view
    plot = client.get(f"/api/jobs/{a['id']}/accuracy").json()
    assert plot["reference_id"] == reference["id"]
    points = {p["job_id"]: p for p in plot["points"]}
    assert {a["id"], b["id"]} <= set(points) and reference["id"] not in points and other_size["id"] not in points
    for job in (a, b):
        point = points[job["id"]]
        assert point["error"] == client.get(f"/api/jobs/{job['id']}/compare/{reference['id']}").json()
        assert point["seconds"] == pytest.approx(job["finished_at"] - job["started_at"])
        assert point["settings"]["samples_per_pixel"] == job["request"]["settings"]["samples_per_pixel"]
    assert points[b["id"]]["error"]["rmse"] < points[a["id"]]["error"]["rmse"], "4 spp is nearer 32 than 1 is"
    assert [p["job_id"] for p in plot["points"]].index(a["id"]) < [p["job_id"] for p in plot["points"]].index(b["id"])
    missing = client.get(f"/api/jobs/{other_size['id']}/accuracy")
    assert missing.status_code == 200 and missing.json() == {"reference_id": "", "points": []}, "no reference: empty"


def test_marking_another_job_of_the_view_replaces_its_reference_and_is_kept_on_disk(client, cornell_id, view):
    reference, a, _, other_size = view
    scene = client.put(f"/api/scenes/{cornell_id}/references/{other_size['id']}").json()
    assert {reference["id"], other_size["id"]} <= set(scene["reference_jobs"]), "one reference per view"
    scene = client.put(f"/api/scenes/{cornell_id}/references/{a['id']}").json()
    assert a["id"] in scene["reference_jobs"] and reference["id"] not in scene["reference_jobs"]
    saved = json.loads((client.app.state.settings.scenes_dir / cornell_id / "scene.json").read_text())
    assert a["id"] in saved["reference_jobs"]
    scene = client.put(f"/api/scenes/{cornell_id}/references/{reference['id']}").json()
    assert client.get(f"/api/jobs/{a['id']}/accuracy").json()["reference_id"] == reference["id"]
    gone = client.delete(f"/api/scenes/{cornell_id}/references/{other_size['id']}")
    assert gone.status_code == 200 and other_size["id"] not in gone.json()["reference_jobs"]
    again = client.delete(f"/api/scenes/{cornell_id}/references/{other_size['id']}")
    assert again.status_code == 404 and "no reference" in again.json()["detail"]


def test_a_job_rendered_as_a_reference_marks_itself_once_done(client, cornell_id, view):
    _, a, _, _ = view
    made = done_job(client, cornell_id, 8, reference=True)
    assert made["request"]["reference"] is True
    assert client.get(f"/api/jobs/{a['id']}/accuracy").json()["reference_id"] == made["id"]
    assert made["id"] in client.get(f"/api/scenes/{cornell_id}").json()["reference_jobs"]


def test_a_job_of_another_scene_or_an_unknown_one_is_refused(client, cornell_id, dragon_id, view):
    _, a, _, _ = view
    wrong = client.put(f"/api/scenes/{dragon_id}/references/{a['id']}")
    assert wrong.status_code == 409 and "not" in wrong.json()["detail"]
    assert client.put(f"/api/scenes/{cornell_id}/references/nojob").status_code == 404
    assert client.put(f"/api/scenes/noscene/references/{a['id']}").status_code == 404


def test_a_camera_a_few_ulps_away_is_the_same_view_and_a_moved_one_is_not(client, cornell_id, view):
    _, a, _, _ = view
    nudged = {**CAMERA, "position": [0.1 + 1e-6, 1.0, 3.2 - 1e-6]}
    same = client.post("/api/jobs", json={"scene_id": cornell_id, "camera": nudged,
                                          "settings": {"width": 40, "height": 30}}).json()
    assert wait_for(client, same["id"])["state"] == "DONE"
    plot = client.get(f"/api/jobs/{same['id']}/accuracy").json()
    assert same["id"] in {p["job_id"] for p in plot["points"]} and a["id"] in {p["job_id"] for p in plot["points"]}
    moved = client.post("/api/jobs", json={"scene_id": cornell_id, "camera": {**CAMERA, "position": [0.3, 1.0, 3.2]},
                                           "settings": {"width": 40, "height": 30}}).json()
    assert wait_for(client, moved["id"])["state"] == "DONE"
    assert client.get(f"/api/jobs/{moved['id']}/accuracy").json()["reference_id"] == ""


def test_a_plot_holds_the_views_newest_jobs_only(client, view, monkeypatch):
    from app.services import references
    _, a, b, _ = view
    monkeypatch.setattr(references, "PLOT_POINTS", 1)
    points = client.get(f"/api/jobs/{a['id']}/accuracy").json()["points"]
    assert len(points) == 1 and points[0]["job_id"] not in (a["id"], b["id"]), "the newest job of the view, not a or b"
