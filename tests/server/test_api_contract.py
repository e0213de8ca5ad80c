"""The API contract, fuzzed: schemathesis (PyPI) generates requests for every
operation of /openapi.json against a real server and checks that none is a
5xx, that every status answered is documented, that every body (errors
included: one shape, {"detail": "..."}) matches its schema, and that 405s
list every method of the resource; its stateful phase follows the
document's links (the scenes to a job, a job to its image, its layer and its
deletion). `make test` runs a short budget
(RT_FUZZ_EXAMPLES, 15 per operation and phase); `make bench` a long one. The
failures it found are kept below as regression tests."""

import os
import re
import subprocess
import sys
from pathlib import Path

from fastapi.testclient import TestClient

from app.main import create_app
from live_server import raw
from service import service_settings

SCHEMATHESIS = Path(sys.executable).with_name("schemathesis")
# Every check but positive_data_acceptance: a request the schema allows may
# still be refused by what it means (a rectangle outside the image: 422).
CHECKS = ["-c", "all", "--exclude-checks", "positive_data_acceptance"]


def schemathesis(port: int, phases: str, folder: Path, examples: int) -> str:
    """A schemathesis run of `phases` against the server; its report, after asserting it found nothing."""
    result = subprocess.run(
        [str(SCHEMATHESIS), "run", f"http://127.0.0.1:{port}/openapi.json", "--max-examples", str(examples),
         "--phases", phases, *CHECKS, "--request-timeout", "30", "--seed", "20261206", "--no-color"],
        capture_output=True, text=True, timeout=1200, cwd=folder)  # its cache goes there
    assert result.returncode == 0, result.stdout[-8000:] + result.stderr[-2000:]
    assert " passed" in result.stdout
    return result.stdout


def test_schemathesis_finds_nothing(live_server, tmp_path):
    # Stateful first: the other phases delete the scenes its links start from.
    examples = int(os.environ.get("RT_FUZZ_EXAMPLES", "15"))
    report = schemathesis(live_server, "stateful", tmp_path, max(examples, 40))
    # It went from the scene list to a job, and on to its image, layer and deletion.
    covered = re.search(r"API Links:\s+(\d+) covered", report)
    assert covered and int(covered.group(1)) >= 3, report[-3000:]
    schemathesis(live_server, "examples,coverage,fuzzing", tmp_path, examples)


def test_a_huge_offset_is_refused_not_a_server_error(live_server):
    answer = raw(live_server, "GET /api/jobs?offset=242019754303600459776 HTTP/1.1", f"Host: 127.0.0.1:{live_server}")
    assert b" 422 " in answer.split(b"\r\n")[0] + b" " and b"offset" in answer


def test_a_405_names_every_method_of_the_resource(tmp_path):
    with TestClient(create_app(service_settings(tmp_path))) as client:
        for path, methods in (("/api/jobs/x", "DELETE, GET, HEAD"), ("/api/jobs/x/pin", "DELETE, PUT"),
                              ("/api/scenes/x", "DELETE, GET, HEAD")):
            answer = client.options(path)
            assert answer.status_code == 405 and answer.headers["allow"] == methods, (path, answer.headers)
            assert answer.json() == {"detail": "Method Not Allowed"}


def test_one_error_shape_documented_everywhere(tmp_path):
    with TestClient(create_app(service_settings(tmp_path))) as client:
        schema = client.get("/openapi.json").json()
        refused = client.get("/api/jobs?limit=0")
    assert refused.status_code == 422 and set(refused.json()) == {"detail"} and "limit" in refused.json()["detail"]
    assert "HTTPValidationError" not in schema["components"]["schemas"]
    error = {"$ref": "#/components/schemas/Error"}
    for path, item in schema["paths"].items():
        for method, operation in item.items():
            for status, response in operation["responses"].items():
                if status.startswith("4"):
                    assert response["content"]["application/json"]["schema"] == error, (method, path, status)
            if "{" in path:
                assert "404" in operation["responses"], (method, path)
    # A light's direction is absent (empty) or three numbers: what the answers hold.
    direction = schema["components"]["schemas"]["rt.LightSpec"]["properties"]["direction"]
    assert direction["anyOf"] == [{"maxItems": 0}, {"minItems": 3}]
