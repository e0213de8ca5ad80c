"""/api/health answers an rt.Health, in the JSON field names the viewer reads."""

from google.protobuf import json_format
from rt import job_pb2


def test_health_is_an_rt_health_message(client):
    answer = client.get("/api/health").json()
    health = json_format.ParseDict(answer, job_pb2.Health())  # no field outside the schema
    assert sorted(answer) == sorted(f.name for f in job_pb2.Health.DESCRIPTOR.fields)
    assert (health.status, health.cluster) == ("ok", "embedded")
    assert health.workers == 1 and health.threads == client.app.state.settings.embedded_threads
    # web/src/main.js reads these, by these names.
    assert isinstance(answer["workers"], int) and isinstance(answer["threads"], int) and answer["status"] == "ok"


def test_openapi_names_the_health_message(client):
    schema = client.get("/openapi.json").json()
    answer = schema["paths"]["/api/health"]["get"]["responses"]["200"]["content"]["application/json"]["schema"]
    assert answer == {"$ref": "#/components/schemas/rt.Health"}
    assert "rt.Health" in schema["components"]["schemas"]
