"""A small PLY reader: ascii, binary_little_endian and binary_big_endian.

Reads every element and property of the header (so files with normals,
colours, confidence values or extra list properties load too), then pulls a
triangle mesh out of the `vertex` and `face` elements, fan-triangulating
polygons. Gzip-compressed files (.ply.gz) are read transparently.
"""

from __future__ import annotations

import gzip
from dataclasses import dataclass
from pathlib import Path

import numpy as np

_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}
_FORMATS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}


class PlyError(ValueError):
    pass


@dataclass
class Property:
    name: str
    dtype: str                  # numpy type code of the value (of each item for lists)
    count_dtype: str | None = None  # set for list properties


@dataclass
class Element:
    name: str
    count: int
    properties: list[Property]


@dataclass
class ListValues:
    """A list property: counts[i] items for instance i, concatenated in `flat`."""
    counts: np.ndarray
    flat: np.ndarray

    def offsets(self) -> np.ndarray:
        return np.concatenate(([0], np.cumsum(self.counts, dtype=np.int64)[:-1]))


def _parse_header(data: bytes, where: str) -> tuple[str | None, list[Element], int]:
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise PlyError(f"{where}: not a PLY file (no 'ply' magic or no end_header)")
    newline = data.find(b"\n", end)
    if newline < 0:
        raise PlyError(f"{where}: header does not end with a newline")
    body_start = newline + 1
    lines = data[:end].decode("ascii", "replace").splitlines()[1:]
    fmt, elements = "", []
    for number, line in enumerate(lines, start=2):
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        try:
            if words[0] == "format":
                if words[1] not in _FORMATS:
                    raise PlyError(f"{where}: unsupported format {words[1]!r}")
                fmt = words[1]
            elif words[0] == "element":
                elements.append(Element(words[1], int(words[2]), []))
                if elements[-1].count < 0:
                    raise PlyError(f"{where}: negative count for element {words[1]!r}")
            elif words[0] == "property":
                if not elements:
                    raise PlyError(f"{where}:{number}: property before any element")
                if words[1] == "list":
                    prop = Property(words[4], _TYPES[words[3]], _TYPES[words[2]])
                    if prop.count_dtype[0] == "f":
                        raise PlyError(f"{where}:{number}: list count must be an integer type")
                else:
                    prop = Property(words[2], _TYPES[words[1]])
                elements[-1].properties.append(prop)
            else:
                raise PlyError(f"{where}:{number}: unknown header line {line!r}")
        except (IndexError, KeyError, ValueError) as err:
            if isinstance(err, PlyError):
                raise
            raise PlyError(f"{where}:{number}: bad header line {line!r}") from None
    if not fmt:
        raise PlyError(f"{where}: header has no format line")
    return _FORMATS[fmt] if fmt != "ascii" else None, elements, body_start


def _first_layout(first_counts: list[int], element: Element) -> list[int]:
    """Items per property of an instance, assuming every instance has the
    list lengths of the first one."""
    it = iter(first_counts)
    return [1 if p.count_dtype is None else next(it) for p in element.properties]


def _split_uniform(columns, element: Element, layout: list[int], n: int) -> dict:
    out = {}
    for prop, items, col in zip(element.properties, layout, columns):
        if prop.count_dtype is None:
            out[prop.name] = col.reshape(n)
        else:
            out[prop.name] = ListValues(np.full(n, items, np.int64), col.reshape(n * items))
    return out


def _read_ascii(tokens: np.ndarray, pos: int, element: Element, where: str):
    n, props = element.count, element.properties
    if n == 0:
        return {p.name: np.zeros(0) for p in props}, pos
    # Fast path: every instance has the list lengths of the first one.
    first, cursor = [], pos
    for p in props:
        if cursor >= tokens.size:
            raise PlyError(f"{where}: file ends inside element {element.name!r}")
        if p.count_dtype is not None:
            first.append(int(tokens[cursor]))
            cursor += 1 + first[-1]
        else:
            cursor += 1
    layout = _first_layout(first, element)
    stride = sum(1 + k if p.count_dtype else 1 for p, k in zip(props, layout))
    if pos + n * stride <= tokens.size:
        block = tokens[pos:pos + n * stride].reshape(n, stride)
        columns, c, uniform = [], 0, True
        for p, k in zip(props, layout):
            if p.count_dtype is not None:
                uniform &= bool(np.all(block[:, c] == k))
                c += 1
            columns.append(block[:, c:c + k].astype(p.dtype))
            c += k
        if uniform:
            return _split_uniform(columns, element, layout, n), pos + n * stride
    # General path: walk the instances one by one.
    values = {p.name: [] for p in props}
    counts = {p.name: [] for p in props if p.count_dtype}
    for _ in range(n):
        for p in props:
            if pos >= tokens.size:
                raise PlyError(f"{where}: file ends inside element {element.name!r}")
            if p.count_dtype is None:
                values[p.name].append(tokens[pos])
                pos += 1
            else:
                k = int(tokens[pos])
                if k < 0 or pos + 1 + k > tokens.size:
                    raise PlyError(f"{where}: bad list length {k} in element {element.name!r}")
                counts[p.name].append(k)
                values[p.name].append(tokens[pos + 1:pos + 1 + k])
                pos += 1 + k
    out = {}
    for p in props:
        if p.count_dtype is None:
            out[p.name] = np.asarray(values[p.name]).astype(p.dtype)
        else:
            flat = np.concatenate(values[p.name]) if values[p.name] else np.zeros(0)
            out[p.name] = ListValues(np.asarray(counts[p.name], np.int64), flat.astype(p.dtype))
    return out, pos


def _read_binary(data: bytes, pos: int, element: Element, endian: str, where: str):
    n, props = element.count, element.properties
    if n == 0:
        return {p.name: np.zeros(0) for p in props}, pos
    first, cursor = [], pos
    for p in props:
        if p.count_dtype is not None:
            size = np.dtype(p.count_dtype).itemsize
            if cursor + size > len(data):
                raise PlyError(f"{where}: file ends inside element {element.name!r}")
            first.append(int(np.frombuffer(data, endian + p.count_dtype, 1, cursor)[0]))
            cursor += size + first[-1] * np.dtype(p.dtype).itemsize
        else:
            cursor += np.dtype(p.dtype).itemsize
    layout = _first_layout(first, element)
    fields = []
    for i, (p, k) in enumerate(zip(props, layout)):
        if p.count_dtype is not None:
            fields.append((f"n{i}", endian + p.count_dtype))
        fields.append((f"v{i}", endian + p.dtype, (k,)))
    record = np.dtype(fields)
    if pos + n * record.itemsize <= len(data):
        block = np.frombuffer(data, record, n, pos)
        uniform = all(np.all(block[f"n{i}"] == k) for i, (p, k) in enumerate(zip(props, layout))
                      if p.count_dtype is not None)
        if uniform:
            columns = [block[f"v{i}"].astype(p.dtype) for i, p in enumerate(props)]
            return _split_uniform(columns, element, layout, n), pos + n * record.itemsize
    values = {p.name: [] for p in props}
    counts = {p.name: [] for p in props if p.count_dtype}
    for _ in range(n):
        for p in props:
            if p.count_dtype is None:
                k, size_n = 1, 0
            else:
                size_n = np.dtype(p.count_dtype).itemsize
                if pos + size_n > len(data):
                    raise PlyError(f"{where}: file ends inside element {element.name!r}")
                k = int(np.frombuffer(data, endian + p.count_dtype, 1, pos)[0])
                if k < 0:
                    raise PlyError(f"{where}: negative list length in element {element.name!r}")
                counts[p.name].append(k)
            end = pos + size_n + k * np.dtype(p.dtype).itemsize
            if end > len(data):
                raise PlyError(f"{where}: file ends inside element {element.name!r}")
            values[p.name].append(np.frombuffer(data, endian + p.dtype, k, pos + size_n))
            pos = end
    out = {}
    for p in props:
        flat = np.concatenate(values[p.name]).astype(p.dtype)
        out[p.name] = flat if p.count_dtype is None else ListValues(
            np.asarray(counts[p.name], np.int64), flat)
    return out, pos


def read_ply(path: Path | str) -> dict[str, dict]:
    """Every element of the file: {element: {property: array or ListValues}}."""
    path = Path(path)
    opener = gzip.open if path.suffix == ".gz" else open
    with opener(path, "rb") as f:
        data = f.read()
    return parse_ply(data, str(path))


def parse_ply(data: bytes, where: str = "<ply>") -> dict[str, dict]:
    endian, elements, pos = _parse_header(data, where)
    result = {}
    if endian is None:
        body = data[pos:].decode("ascii", "replace")
        tokens = np.fromstring(body, dtype=np.float64, sep=" ") if body.strip() else np.zeros(0)
        pos = 0
        for element in elements:
            result[element.name], pos = _read_ascii(tokens, pos, element, where)
    else:
        for element in elements:
            result[element.name], pos = _read_binary(data, pos, element, endian, where)
    return result


def triangulate(faces: ListValues) -> np.ndarray:
    """(n, 3) triangles from polygons, as fans around each polygon's first vertex.
    Polygons with fewer than 3 vertices are dropped."""
    out, offsets = [], faces.offsets()
    for k in np.unique(faces.counts):
        if k < 3:
            continue
        polys = faces.flat[offsets[faces.counts == k][:, None] + np.arange(k)]
        for j in range(1, k - 1):
            out.append(polys[:, [0, j, j + 1]])
    return np.concatenate(out).astype(np.int64) if out else np.zeros((0, 3), np.int64)


def read_ply_mesh(path: Path | str) -> tuple[np.ndarray, np.ndarray]:
    """float32 positions (n, 3) and uint32 triangles (m, 3), checked for range."""
    elements = read_ply(path)
    vertex, face = elements.get("vertex"), elements.get("face")
    if vertex is None or face is None:
        raise PlyError(f"{path}: needs 'vertex' and 'face' elements")
    if not all(isinstance(vertex.get(c), np.ndarray) for c in "xyz"):
        raise PlyError(f"{path}: vertex element has no x, y, z properties")
    indices = face.get("vertex_indices", face.get("vertex_index"))
    if not isinstance(indices, ListValues):
        raise PlyError(f"{path}: face element has no vertex_indices list")
    positions = np.stack([vertex[c] for c in "xyz"], axis=1).astype(np.float32)
    if not np.all(np.isfinite(positions)):
        raise PlyError(f"{path}: non-finite vertex coordinates")
    triangles = triangulate(indices)
    if triangles.size and (triangles.min() < 0 or triangles.max() >= len(positions)):
        raise PlyError(f"{path}: face index out of range (vertices: {len(positions)})")
    return positions, triangles.astype(np.uint32)
