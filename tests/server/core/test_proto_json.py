"""core/proto.py's JSON answers: kept by the message's bytes, so that a record
asked for again is not converted again, and a changed one is."""

from rt import job_pb2

from app.core.proto import to_dict


def test_an_equal_message_answers_the_same_json_and_a_changed_one_its_own():
    job = job_pb2.Job(id="a1", state=job_pb2.DONE, tiles_done=4)
    first = to_dict(job)
    assert to_dict(job_pb2.Job.FromString(job.SerializeToString())) is first
    job.pinned = True
    changed = to_dict(job)
    assert changed is not first and changed["pinned"] is True and first["pinned"] is False
    assert changed["state"] == "DONE" and changed["tiles_done"] == 4 and changed["error"] == ""


def test_messages_of_different_types_with_the_same_bytes_answer_their_own():
    assert to_dict(job_pb2.Job()) != to_dict(job_pb2.JobList())


def test_a_large_message_is_converted_each_time_not_kept():
    from app.core.proto import KEPT_MESSAGE_BYTES

    large = job_pb2.Job(id="b2", error="x" * (KEPT_MESSAGE_BYTES + 1))
    assert to_dict(large) == to_dict(large) and to_dict(large) is not to_dict(large)
