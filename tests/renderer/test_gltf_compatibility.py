"""docs/gltf.md, walked row by row.

Each supported or approximated row names an asset: it must exist, exercise its
feature (a probe over the asset's JSON, one per feature below) and load; a
supported feature's asset loads without a warning that something was skipped
or not supported, an approximated one with the row's message. Rows without an
asset are extensions: a file that uses one must load with the row's warning,
and a file that requires one must be refused. Refused rows are refused with
their message.
"""
from __future__ import annotations

import json
import re
import struct
from pathlib import Path

import pytest

import rtcore
from rt import job_pb2

ROOT = Path(__file__).resolve().parents[2]
TABLE_ROW = re.compile(r"^\| `([^`]+)` \| (supported|approximated|refused) \| (.*?) \| (.*?) \| (.*?) \|$")
NOT_SUPPORTED = re.compile(r"not supported|skipped|ignored")


def table_rows() -> list[dict]:
    rows = []
    for line in (ROOT / "docs" / "gltf.md").read_text().splitlines():
        match = TABLE_ROW.match(line)
        if match:
            feature, status, _, message, asset = match.groups()
            quoted = lambda cell: (re.findall(r"`([^`]+)`", cell) or [None])[0]  # noqa: E731
            rows.append({"feature": feature, "status": status, "message": quoted(message),
                         "asset": quoted(asset)})
    return rows


ROWS = table_rows()


def gltf_json(path: Path) -> dict:
    data = path.read_bytes()
    if data[:4] != b"glTF":
        return json.loads(data)
    length, _ = struct.unpack_from("<II", data, 12)
    return json.loads(data[20:20 + length])


def primitives(doc):
    for mesh in doc.get("meshes", []):
        yield from mesh.get("primitives", [])


def materials(doc):
    return doc.get("materials", [])


def any_attribute(doc, name):
    return any(name in p["attributes"] for p in primitives(doc))


def mode(doc, *modes):
    return any(p.get("mode", 4) in modes for p in primitives(doc))


def has_uri(doc, predicate):
    return any(predicate(item.get("uri", "")) for key in ("buffers", "images") for item in doc.get(key, []))


# What makes an asset exercise each core feature: a row without one fails.
PROBES = {
    "glb": lambda doc, path: path.suffix == ".glb",
    "external files": lambda doc, path: has_uri(doc, lambda u: u and not u.startswith("data:")),
    "data URIs": lambda doc, path: has_uri(doc, lambda u: u.startswith("data:")),
    "node hierarchy": lambda doc, path: any("children" in n for n in doc["nodes"])
    and any("matrix" in n for n in doc["nodes"]) and any("rotation" in n for n in doc["nodes"]),
    "TRIANGLES": lambda doc, path: mode(doc, 4),
    "TRIANGLE_STRIP": lambda doc, path: mode(doc, 5),
    "TRIANGLE_FAN": lambda doc, path: mode(doc, 6),
    "POINTS and LINES": lambda doc, path: mode(doc, 0, 1, 2, 3),
    "NORMAL": lambda doc, path: any_attribute(doc, "NORMAL"),
    "TANGENT": lambda doc, path: any_attribute(doc, "TANGENT"),
    "TEXCOORD_0 and TEXCOORD_1": lambda doc, path: any_attribute(doc, "TEXCOORD_1"),
    "COLOR_0": lambda doc, path: any_attribute(doc, "COLOR_0"),
    "sparse accessors": lambda doc, path: any("sparse" in a and "bufferView" in a for a in doc["accessors"]),
    "accessors without a buffer view": lambda doc, path: any("bufferView" not in a for a in doc["accessors"]),
    "skins": lambda doc, path: bool(doc.get("skins")),
    "morph targets": lambda doc, path: any(p.get("targets") for p in primitives(doc)),
    "animations": lambda doc, path: bool(doc.get("animations")),
    "perspective cameras": lambda doc, path: any(c["type"] == "perspective" for c in doc.get("cameras", [])),
    "orthographic cameras": lambda doc, path: any(c["type"] == "orthographic" for c in doc.get("cameras", [])),
    "pbrMetallicRoughness": lambda doc, path: any("pbrMetallicRoughness" in m for m in materials(doc)),
    "baseColorTexture": lambda doc, path: any("baseColorTexture" in m.get("pbrMetallicRoughness", {})
                                              for m in materials(doc)),
    "metallicRoughnessTexture": lambda doc, path: any("metallicRoughnessTexture" in m.get("pbrMetallicRoughness", {})
                                                      for m in materials(doc)),
    "normalTexture": lambda doc, path: any("normalTexture" in m for m in materials(doc)),
    "occlusionTexture": lambda doc, path: any("occlusionTexture" in m for m in materials(doc)),
    "emission": lambda doc, path: any("emissiveTexture" in m for m in materials(doc)),
    "alphaMode MASK": lambda doc, path: any(m.get("alphaMode") == "MASK" for m in materials(doc)),
    "alphaMode BLEND": lambda doc, path: any(m.get("alphaMode") == "BLEND" for m in materials(doc)),
    "doubleSided": lambda doc, path: any(m.get("doubleSided") for m in materials(doc)),
    "sampler wrap modes": lambda doc, path: {s.get("wrapS") for s in doc.get("samplers", [])} >= {33071, 33648},
    "sampler filters": lambda doc, path: bool(doc.get("samplers")),
    "PNG and JPEG images": lambda doc, path: {i.get("mimeType") for i in doc.get("images", [])}
    >= {"image/png", "image/jpeg"},
}


def probe(feature: str):
    if re.match(r"^(KHR|EXT)_", feature):
        return lambda doc, path: feature in doc.get("extensionsUsed", [])
    return PROBES[feature]


def find_asset(name: str, assets_dir: Path, scenes_dir: Path) -> Path:
    for folder in (assets_dir, scenes_dir):
        if (folder / name).exists():
            return folder / name
    pytest.fail(f"docs/gltf.md names asset {name}, which neither {assets_dir} nor {scenes_dir} has")


def warnings_of(path: Path) -> list[str]:
    return list(job_pb2.SceneInfo.FromString(rtcore.Scene.load(str(path)).info).warnings)


def minimal_gltf(folder: Path, extension: str, required: bool) -> Path:
    """One triangle in a file that uses (or requires) `extension`."""
    import base64
    import numpy as np
    data = np.array([0, 0, 0, 1, 0, 0, 0, 1, 0], "<f4").tobytes()
    doc = {
        "asset": {"version": "2.0"}, "extensionsUsed": [extension],
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0,
    }
    if required:
        doc["extensionsRequired"] = [extension]
    path = folder / f"{extension}{'_required' if required else ''}.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_the_table_is_complete():
    features = [row["feature"] for row in ROWS]
    assert len(features) == len(set(features)), "a feature is listed twice"
    assert len(ROWS) >= 60, f"docs/gltf.md's tables have {len(ROWS)} rows; did the format change?"
    core = [f for f in features if not re.match(r"^(KHR|EXT)_", f)]
    assert set(core) == set(PROBES), "every core row needs a probe here, and every probe a row"
    for row in ROWS:
        if row["status"] != "supported" and not row["asset"]:
            assert row["message"], f"{row['feature']}: a row without an asset needs the message a user sees"


@pytest.mark.parametrize("row", [r for r in ROWS if r["asset"]], ids=lambda r: r["feature"])
def test_each_asset_exercises_its_feature(row, assets_dir, scenes_dir):
    path = find_asset(row["asset"], assets_dir, scenes_dir)
    assert probe(row["feature"])(gltf_json(path), path), f"{path.name} does not exercise {row['feature']}"
    warnings = warnings_of(path)
    if row["status"] == "supported":
        assert not [w for w in warnings if NOT_SUPPORTED.search(w)], warnings
    elif row["message"]:
        assert any(row["message"] in w for w in warnings), (row["message"], warnings)


@pytest.mark.parametrize("row", [r for r in ROWS if not r["asset"] and r["status"] == "approximated"],
                         ids=lambda r: r["feature"])
def test_an_approximated_extension_warns_and_is_refused_when_required(row, tmp_path):
    extension = row["feature"]
    warnings = warnings_of(minimal_gltf(tmp_path, extension, required=False))
    assert any(f"uses the glTF extension '{extension}'" in w and row["message"] in w for w in warnings), warnings
    with pytest.raises(ValueError, match=f"requires the glTF extension '{extension}', which is not supported"):
        rtcore.Scene.load(str(minimal_gltf(tmp_path, extension, required=True)))


@pytest.mark.parametrize("row", [r for r in ROWS if r["status"] == "refused"], ids=lambda r: r["feature"])
def test_a_refused_feature_is_refused_with_its_message(row, tmp_path):
    with pytest.raises(ValueError, match=re.escape(row["message"])):
        rtcore.Scene.load(str(minimal_gltf(tmp_path, row["feature"], required=True)))


def test_a_supported_extension_is_not_refused_when_required(tmp_path):
    # The loader's list and the table's agree: every supported extension loads
    # when a file requires it.
    for row in ROWS:
        if row["status"] == "supported" and re.match(r"^(KHR|EXT)_", row["feature"]):
            rtcore.Scene.load(str(minimal_gltf(tmp_path, row["feature"], required=True)))
