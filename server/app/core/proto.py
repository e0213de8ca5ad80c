"""The proto/ schema on the Python side: request bodies in, JSON out, and the
OpenAPI schemas /docs shows, all from the generated code.

Render requests are completed and validated by rtcore (C++), the same code the
CLI and the workers use, so every side fills the same defaults and refuses the
same values.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

import rtcore
from google.protobuf import descriptor as _descriptor
from google.protobuf.json_format import MessageToDict
from google.protobuf.message import Message
from rt import debug_pb2, job_pb2, options_pb2, render_pb2, scene_pb2

M = TypeVar("M", bound=Message)

FILES = (render_pb2, scene_pb2, debug_pb2, job_pb2)


def normalize(message_type: type[M], body: bytes | str, scene_of: Callable[[M], rtcore.Scene]) -> M:
    """The one way a render request (rt.JobRequest, rt.DebugRayRequest) enters:
    its JSON read (field names and types), the scene it is for found by
    `scene_of` (which raises what a missing scene is), then completed and
    checked once by that scene (rtcore Scene.complete): absent settings take
    the schema's defaults, an absent camera the scene's default view, every
    field its limits, and the camera and settings the renderer's own checks.
    Raises ValueError naming the field as API users write it."""
    text = body.decode("utf-8", errors="strict") if isinstance(body, bytes) else body
    if not text.strip():
        raise ValueError("body: expected a JSON object, got an empty body")
    name = message_type.DESCRIPTOR.full_name
    read = rtcore.parse_message(name, text, "body", limits=False)
    scene = scene_of(message_type.FromString(read))
    return message_type.FromString(scene.complete(name, read))


def to_dict(message: Message) -> dict[str, Any]:
    """The JSON form we answer with: proto field names, every field present.
    Shared with every answer of the same message: read it, never change it.

    MessageToDict is pure Python, and clients ask for the same records again
    and again (a job that has ended never changes; lists and polls repeat
    it): under the load benchmark it was 5% of the event loop's time. So the
    answer to a small message (a job's record is about 1 KB) is kept by the
    message's bytes, which serialize in C; large ones (a BVH level's boxes, a
    traced pixel's rays) are rarely asked for twice and would crowd the rest
    out."""
    serialized = message.SerializeToString(deterministic=True)
    if len(serialized) > KEPT_MESSAGE_BYTES:
        return MessageToDict(message, preserving_proto_field_name=True, including_default_value_fields=True)
    return _dict_of(type(message), serialized)


# Answers kept: at most 4096 of at most 16 KB each (their dicts take a few times that).
KEPT_MESSAGE_BYTES = 16 * 1024


@functools.lru_cache(maxsize=4096)
def _dict_of(message_type: type[Message], serialized: bytes) -> dict[str, Any]:
    return MessageToDict(message_type.FromString(serialized), preserving_proto_field_name=True,
                         including_default_value_fields=True)


def to_json_text(message: Message) -> str:
    import json

    return json.dumps(MessageToDict(message, preserving_proto_field_name=True))


# --- OpenAPI -----------------------------------------------------------------

_SCALARS = {
    _descriptor.FieldDescriptor.TYPE_DOUBLE: {"type": "number"},
    _descriptor.FieldDescriptor.TYPE_FLOAT: {"type": "number"},
    _descriptor.FieldDescriptor.TYPE_INT32: {"type": "integer"},
    _descriptor.FieldDescriptor.TYPE_UINT32: {"type": "integer", "minimum": 0},
    _descriptor.FieldDescriptor.TYPE_SINT32: {"type": "integer"},
    # The proto JSON form writes 64-bit integers as strings.
    _descriptor.FieldDescriptor.TYPE_INT64: {"type": ["integer", "string"]},
    _descriptor.FieldDescriptor.TYPE_UINT64: {"type": ["integer", "string"]},
    _descriptor.FieldDescriptor.TYPE_BOOL: {"type": "boolean"},
    _descriptor.FieldDescriptor.TYPE_STRING: {"type": "string"},
    _descriptor.FieldDescriptor.TYPE_BYTES: {"type": "string", "contentEncoding": "base64"},
}


def schema_ref(message_type: type[Message] | _descriptor.Descriptor) -> dict[str, str]:
    descriptor = getattr(message_type, "DESCRIPTOR", message_type)
    return {"$ref": f"#/components/schemas/{descriptor.full_name}"}


def _field_schema(field: _descriptor.FieldDescriptor) -> tuple[dict[str, Any], bool]:
    limits = field.GetOptions().Extensions[options_pb2.limits]
    if field.type == field.TYPE_MESSAGE:
        item: dict[str, Any] = schema_ref(field.message_type)
    elif field.type == field.TYPE_ENUM:
        item = {"type": "string", "enum": [v.name for v in field.enum_type.values]}
        if field.label != field.LABEL_REPEATED:
            item["default"] = field.enum_type.values_by_number[0].name  # proto3: the zero value
    else:
        item = dict(_SCALARS[field.type])
        if limits.HasField("min"):
            item["minimum"] = limits.min
        if limits.HasField("max"):
            item["maximum"] = limits.max
    if field.label == field.LABEL_REPEATED:
        schema: dict[str, Any] = {"type": "array", "items": item}
        if limits.count and limits.required:
            schema["minItems"] = schema["maxItems"] = limits.count
        elif limits.count:  # absent (empty), or exactly `count`
            schema["maxItems"] = limits.count
            schema["anyOf"] = [{"maxItems": 0}, {"minItems": limits.count}]
    else:
        schema = item
        if limits.HasField("default"):
            schema = {**schema, "default": limits.default}
    return schema, limits.required


def _message_schema(descriptor: _descriptor.Descriptor) -> dict[str, Any]:
    properties, required = {}, []
    for field in descriptor.fields:
        properties[field.name], is_required = _field_schema(field)
        if is_required:
            required.append(field.name)
    schema: dict[str, Any] = {"type": "object", "title": descriptor.name, "properties": properties,
                              "additionalProperties": False}
    if required:
        schema["required"] = required
    return schema


def openapi_components() -> dict[str, Any]:
    """A JSON schema for every message of the rt package."""
    schemas = {}
    for module in FILES:
        for descriptor in module.DESCRIPTOR.message_types_by_name.values():
            schemas[descriptor.full_name] = _message_schema(descriptor)
    return schemas


def json_body(message_type: type[Message]) -> dict[str, Any]:
    """openapi_extra for a route that reads the JSON form of `message_type`."""
    return {"requestBody": {"required": True, "content": {"application/json": {"schema": schema_ref(message_type)}}}}


def json_response(message_type: type[Message], description: str) -> dict[str, Any]:
    return {"description": description, "content": {"application/json": {"schema": schema_ref(message_type)}}}
