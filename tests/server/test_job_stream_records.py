"""The job's record on its tile stream: published as its state and progress
change, so that a viewer follows the job without asking for it again."""

import asyncio

from rt import job_pb2

from app.services.streams import TileStream
from stream_reader import read_stream


def submit(client, scene_id, width, height, **settings):
    body = {"scene_id": scene_id, "settings": {"width": width, "height": height, **settings}}
    response = client.post("/api/jobs", json=body)
    assert response.status_code == 202, response.text
    return response.json()


def kind(message) -> str:
    return message.WhichOneof("message")


def check_records(messages) -> list[job_pb2.Job]:
    """The stream's records, checked against the tiles around them and its end."""
    records = [m.job for m in messages if kind(m) == "job"]
    end = messages[-1].end
    assert kind(messages[-1]) == "end" and end.state == job_pb2.DONE
    assert records, "the stream carried no record before its end"
    tiles_before = 0
    for m in messages:
        if kind(m) == "tile":
            tiles_before += 1
        elif kind(m) == "job":
            # A record follows the tiles it counts.
            assert m.job.tiles_done <= tiles_before
            assert m.job.state == job_pb2.RUNNING and m.job.id == end.id and m.job.request == end.request
    for a, b in zip(records, records[1:]):
        assert b.progress >= a.progress and b.tiles_done > a.tiles_done and b.rays >= a.rays
        assert b.render_seconds >= a.render_seconds and b.started_at == a.started_at
    last = records[-1]
    assert kind(messages[-2]) == "job", "the last record comes right before the end"
    assert last.progress == 1 and last.tiles_done == last.tiles_total == end.tiles_total == tiles_before
    for name in ("started_at", "rays", "render_seconds", "mean_samples_per_pixel", "passes"):
        assert getattr(last, name) == getattr(end, name), name
    assert last.started_at > 0 and last.finished_at == 0 < end.finished_at
    return records


def test_the_stream_carries_the_record_as_the_job_runs(client, cornell_id):
    # Several tiles over a preview and a full pass: progress has steps to rise by.
    job = submit(client, cornell_id, 300, 240)
    messages = read_stream(client, job["id"])
    records = check_records(messages)
    assert len({r.progress for r in records}) == len(records), "one record per change"


def test_a_bloomed_job_s_last_record_counts_the_bloom_tile(client, cornell_id):
    job = submit(client, cornell_id, 96, 72, bloom_strength=0.5)
    messages = read_stream(client, job["id"])
    records = check_records(messages)
    assert records[-1].passes == 2 and kind(messages[-3]) == "tile" and messages[-3].tile.region.w == 96


def test_a_late_viewer_gets_the_latest_record_only(client, cornell_id):
    job = submit(client, cornell_id, 200, 150)
    early = read_stream(client, job["id"])
    late = read_stream(client, job["id"])  # after the end: the kept stream replays
    assert len([m for m in early if kind(m) == "job"]) >= 1
    assert [m.SerializeToString() for m in late if kind(m) != "job"] == \
        [m.SerializeToString() for m in early if kind(m) != "job"]
    assert [kind(m) for m in late[-2:]] == ["job", "end"] and [kind(m) for m in late].count("job") == 1
    assert late[-2] == [m for m in early if kind(m) == "job"][-1]


def test_a_viewer_behind_skips_the_records_it_missed_and_gets_each_new_one_once():
    def record(done: int) -> job_pb2.Job:
        return job_pb2.Job(id="j", state=job_pb2.RUNNING, tiles_done=done, tiles_total=3, progress=done / 3)

    def tile(x: int) -> bytes:
        return job_pb2.TileStreamMessage(tile=job_pb2.Tile(job="j", region=job_pb2.TileRegion(x=x))).SerializeToString()

    async def scenario():
        stream = TileStream()
        for done in (1, 2):
            await stream.publish(tile(done))
            await stream.update(record(done))
        received = []
        follower = stream.follow()
        received.append(await anext(follower))  # tile 1
        received.append(await anext(follower))  # tile 2
        received.append(await anext(follower))  # the latest record only
        waiting = asyncio.ensure_future(anext(follower))
        await asyncio.sleep(0)
        assert not waiting.done(), "nothing new: the viewer waits"
        await stream.publish(tile(3))
        await stream.update(record(3))
        received.append(await waiting)
        received.append(await anext(follower))
        await stream.finish(record(3))
        received += [m async for m in follower]
        return [job_pb2.TileStreamMessage.FromString(m) for m in received]

    messages = asyncio.run(asyncio.wait_for(scenario(), 5))
    assert [kind(m) for m in messages] == ["tile", "tile", "job", "tile", "job", "end"]
    assert [m.job.tiles_done for m in messages if kind(m) == "job"] == [2, 3]
