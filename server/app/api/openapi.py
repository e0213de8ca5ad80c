"""The OpenAPI document: FastAPI's, with the proto messages as schemas and
one error shape for the whole API.

Every error answer is `{"detail": "<what is wrong, naming it>"}` (the Error
schema), 422s included: FastAPI's HTTPValidationError list is replaced where
the app answers otherwise (main.validation_error). Each operation documents
the errors it can answer: those any request can meet (a foreign Host, a
missing token, another site's Origin on a state-changing one), those of its
path parameters and body, and those its route declares itself.
"""

from __future__ import annotations

from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import get_openapi

from ..core.local_access import STATE_CHANGING
from ..core.proto import openapi_components

ERROR_SCHEMA = {"type": "object", "title": "Error", "required": ["detail"], "additionalProperties": False,
                "properties": {"detail": {"type": "string", "description": "What is wrong, naming the field or thing"}}}
ERROR_CONTENT = {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}

ANY_REQUEST = {"400": "The Host header is not this server's name (RT_ALLOWED_HOSTS)"}
API_REQUEST = {"401": "This server needs an API token, and it is missing or wrong"}
STATE_CHANGE = {"403": "A browser's request from another site's page (RT_ALLOWED_ORIGINS)"}
PATH_NAMES = {"404": "No such scene or job, or no such image or layer of it"}
INPUT = {"422": "A parameter or body the route cannot take; the detail names it"}
# Routes of a job's images, layers and comparisons answer 409 until it is done.
NOT_DONE = {"409": "The job is not done: its images exist once it is"}
UPLOAD = {"413": "The upload is over this server's limits, or over the user's quota of stored bytes (RT_QUOTA_MB)",
          "415": "Not a scene file this server reads"}
# What stores something (a state change; a job's image made when first asked for) can find the disk full.
STORAGE = {"507": "The server's data folder is full"}


def _errors(path: str, method: str, operation: dict[str, Any]) -> dict[str, str]:
    wanted = dict(ANY_REQUEST)
    if path.startswith("/api/"):
        wanted |= API_REQUEST
    if method.upper() in STATE_CHANGING:
        wanted |= STATE_CHANGE | STORAGE
    if "{" in path:
        wanted |= PATH_NAMES
    if operation.get("parameters") or operation.get("requestBody"):
        wanted |= INPUT
    if path.startswith("/api/jobs/{job_id}/") and method == "get":
        wanted |= NOT_DONE | STORAGE
    if path == "/api/scenes" and method == "post":
        wanted |= UPLOAD
    return wanted


# How answers lead to the next request (OpenAPI links), for clients and for
# schemathesis's stateful runs: a scene to its jobs, a job to its image, its
# layers and its deletion. (path, method, status) -> {name: (operation, parameters, body)}.
SCENE_ID = "$response.body#/id"
FIRST_SCENE_ID = "$response.body#/scenes/0/id"
JOB_ID = "$response.body#/id"
SMALL = {"width": 16, "height": 12}
LINKS = {
    ("/api/scenes", "get", "200"): {
        "GetScene": ("get_scene", {"scene_id": FIRST_SCENE_ID}, None),
        "SubmitJob": ("submit_job", {}, {"scene_id": FIRST_SCENE_ID, "settings": SMALL}),
    },
    ("/api/scenes", "post", "201"): {
        "GetScene": ("get_scene", {"scene_id": SCENE_ID}, None),
        "SubmitJob": ("submit_job", {}, {"scene_id": SCENE_ID, "settings": SMALL}),
        "DeleteScene": ("delete_scene", {"scene_id": SCENE_ID}, None),
    },
    ("/api/jobs", "post", "202"): {
        "GetJob": ("get_job", {"job_id": JOB_ID}, None),
        "GetImage": ("job_png", {"job_id": JOB_ID, "name": "image"}, None),
        "GetLayer": ("job_layer", {"job_id": JOB_ID, "name": "color"}, None),
        "DeleteJob": ("delete_job", {"job_id": JOB_ID}, None),
    },
}


def _links(schema: dict[str, Any]) -> None:
    # FastAPI's operationId is the route function's name, then "_api_" and the path.
    ids = {op["operationId"].split("_api_")[0]: op["operationId"]
           for item in schema["paths"].values() for op in item.values()}
    for (path, method, status), links in LINKS.items():
        response = schema["paths"][path][method]["responses"][status]
        response["links"] = {
            name: {"operationId": ids[operation], **({"parameters": parameters} if parameters else {}),
                   **({"requestBody": body} if body else {})}
            for name, (operation, parameters, body) in links.items()}


def build_schema(app: FastAPI) -> dict[str, Any]:
    schema = get_openapi(title=app.title, version="1", summary=app.summary, routes=app.routes)
    components = schema.setdefault("components", {}).setdefault("schemas", {})
    components.update(openapi_components())
    components.pop("HTTPValidationError", None)
    components.pop("ValidationError", None)
    components["Error"] = ERROR_SCHEMA
    for path, item in schema["paths"].items():
        for method, operation in item.items():
            responses = operation.setdefault("responses", {})
            for status, description in _errors(path, method, operation).items():
                if status == "422" or status not in responses:
                    responses[status] = {"description": description}
            for status, response in responses.items():
                if status.startswith(("4", "5")):
                    response["content"] = ERROR_CONTENT
    _links(schema)
    return schema
