"""Several jobs share the cluster: equal jobs advance together, and a small
interactive job runs ahead of a big batch job instead of waiting for it."""

import time

from stream_reader import wait_for


def post_job(client, scene_id, width, height, samples=1, **extra):
    body = {"scene_id": scene_id, "settings": {"width": width, "height": height, "samples_per_pixel": samples}, **extra}
    response = client.post("/api/jobs", json=body)
    assert response.status_code == 202, response.text
    return response.json()["id"]


def test_an_interactive_job_is_not_stuck_behind_a_big_one(client, dragon_id):
    big = post_job(client, dragon_id, 1600, 1200, samples=4)  # 35 tiles of 256 after 4 preview tiles
    while client.get(f"/api/jobs/{big}").json()["tiles_done"] < 4:
        time.sleep(0.02)
    submitted = time.monotonic()
    small = post_job(client, dragon_id, 160, 120, interactive=True)
    done = wait_for(client, small, timeout=60)
    waited = time.monotonic() - submitted
    big_now = client.get(f"/api/jobs/{big}").json()
    client.delete(f"/api/jobs/{big}")
    assert done["state"] == "DONE"
    assert big_now["state"] == "RUNNING", "the big job should still be running when the small one is done"
    assert big_now["tiles_done"] < big_now["tiles_total"] / 2
    assert waited < 5, f"the interactive job took {waited:.1f} s"


def test_equal_jobs_advance_together(client, dragon_id):
    # 16 samples a pixel: tiles of 128, 12 to a job, so that the second job's
    # first tiles are ready while the first job still has most of its own to go.
    first = post_job(client, dragon_id, 512, 384, samples=16)
    second = post_job(client, dragon_id, 512, 384, samples=16)
    wait_for(client, first, timeout=120)
    other = client.get(f"/api/jobs/{second}").json()
    assert other["tiles_done"] >= 0.6 * other["tiles_total"], other
    wait_for(client, second, timeout=120)
