"""Uploads into scene folders: what is accepted loads, everything else is refused
with the right status, early, and without a byte written outside the folder."""
import hashlib
import io
import json
import os
import stat
import struct
import warnings
import zipfile
from pathlib import Path

import pytest

import rtcore
from rt import job_pb2

from app.api.errors import http_status
from app.services import uploads
from app.services.uploads import StoredUpload, UploadError, store_upload

MB = 1 << 20
LIMITS = dict(max_bytes=64 * MB, max_unpacked_bytes=64 * MB, max_files=100)


@pytest.fixture
def folder(tmp_path) -> Path:
    """A fresh empty scene folder, with a sibling the upload must never touch."""
    parent = tmp_path / "scenes"
    (parent / "other-scene").mkdir(parents=True)
    (parent / "other-scene" / "keep.txt").write_text("mine")
    scene_folder = parent / "new-scene"
    scene_folder.mkdir()
    return scene_folder


def scene_info(scene_file: Path) -> job_pb2.SceneInfo:
    return job_pb2.SceneInfo.FromString(rtcore.Scene.load(str(scene_file)).info)


def store(folder, filename, data, **limits) -> StoredUpload:
    return store_upload(filename, io.BytesIO(data), folder, **{**LIMITS, **limits})


def tree(path: Path) -> dict[str, int]:
    """Every path below `path` (symlinks not followed) with its size."""
    found = {}
    for root, dirs, files in os.walk(path):
        for name in dirs + files:
            full = Path(root, name)
            found[str(full.relative_to(path))] = full.lstat().st_size
    return found


def refused(folder, filename, data, status, words, **limits) -> UploadError:
    """Asserts the refusal, and that it left the folder empty and its parent as it was."""
    parent_before = tree(folder.parent)
    with pytest.raises(UploadError) as caught:
        store(folder, filename, data, **limits)
    assert http_status(caught.value) == status, str(caught.value)
    assert words in str(caught.value)
    assert tree(folder.parent) == parent_before
    assert list(folder.iterdir()) == []
    return caught.value


def make_zip(entries, compression=zipfile.ZIP_DEFLATED) -> bytes:
    """entries: (name or ZipInfo, bytes) pairs, names kept exactly as given."""
    buffer = io.BytesIO()
    with warnings.catch_warnings(), zipfile.ZipFile(buffer, "w", compression) as archive:
        warnings.simplefilter("ignore")  # zipfile warns about the duplicates we write on purpose
        for name, data in entries:
            archive.writestr(name, data)
    written = zipfile.ZipFile(io.BytesIO(buffer.getvalue())).namelist()
    assert written == [getattr(name, "filename", name) for name, _ in entries]
    return buffer.getvalue()


def patch_headers(data: bytes, *, flag_bits=0, uncompressed_size=None) -> bytes:
    """Rewrites every local and central header: what a hostile zip writer can do."""
    out = bytearray(data)
    for signature, flags_at, size_at in ((b"PK\x03\x04", 6, 22), (b"PK\x01\x02", 8, 24)):
        at = out.find(signature)
        while at >= 0:
            flags = struct.unpack_from("<H", out, at + flags_at)[0]
            struct.pack_into("<H", out, at + flags_at, flags | flag_bits)
            if uncompressed_size is not None:
                struct.pack_into("<I", out, at + size_at, uncompressed_size)
            at = out.find(signature, at + 4)
    return bytes(out)


@pytest.fixture(scope="module")
def cornell(scenes_dir) -> list[tuple[str, bytes]]:
    return [(name, (scenes_dir / name).read_bytes()) for name in ("cornell.obj", "cornell.mtl", "cornell.rt.json")]


# --- accepted uploads store a scene the renderer loads -----------------------------------------

def test_glb_is_stored_with_its_size_and_hash_and_loads(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    stored = store(folder, "My Bunny.GLB", data)
    assert stored == StoredUpload(folder, folder / "My Bunny.glb", "glb", len(data), hashlib.sha256(data).hexdigest())
    assert stored.scene_file.read_bytes() == data
    assert rtcore.Scene.load(str(stored.scene_file)).triangle_count > 1000


def test_obj_alone_loads_with_warnings_about_its_missing_mtl(folder, cornell):
    stored = store(folder, "cornell.obj", cornell[0][1])
    assert stored.format == "obj"
    scene = scene_info(stored.scene_file)
    assert scene.triangle_count >= 30
    assert any("cornell.mtl" in warning for warning in scene.warnings)


def test_zip_of_obj_mtl_and_sidecar_loads_all_three(folder, cornell):
    data = make_zip(cornell)
    stored = store(folder, "cornell.zip", data)
    assert (stored.scene_file, stored.format, stored.size_bytes) == (folder / "cornell.obj", "obj", len(data))
    assert stored.sha256 == hashlib.sha256(data).hexdigest()  # of the zip as received
    assert sorted(tree(folder)) == ["cornell.mtl", "cornell.obj", "cornell.rt.json"]  # the zip itself is gone
    scene = scene_info(stored.scene_file)
    assert scene.warnings == [] and len(scene.lights) == 1 and len(scene.cameras) == 2


def test_zip_with_the_scene_in_a_subfolder_loads_from_there(folder, cornell):
    stored = store(folder, "box.zip", make_zip([("models/", b"")] + [(f"models/box/{n}", d) for n, d in cornell]))
    assert stored.scene_file == folder / "models" / "box" / "cornell.obj"
    assert len(scene_info(stored.scene_file).lights) == 1


def test_zip_with_windows_backslash_folders_unpacks_into_folders(folder, cornell):
    stored = store(folder, "box.zip", make_zip([("models\\", b"")] + [(f"models\\{n}", d) for n, d in cornell]))
    assert stored.scene_file == folder / "models" / "cornell.obj"
    assert len(scene_info(stored.scene_file).lights) == 1


def test_zip_of_gltf_with_an_external_buffer_loads_the_buffer(folder):
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": len(positions)}],
        "buffers": [{"uri": "triangle.bin", "byteLength": len(positions)}],
    }
    data = make_zip([("triangle.gltf", json.dumps(gltf)), ("triangle.bin", positions)])
    stored = store(folder, "triangle.zip", data)
    assert stored.format == "gltf"
    assert rtcore.Scene.load(str(stored.scene_file)).triangle_count == 1


def test_zip_from_macos_finder_ignores_its_resource_forks(folder, cornell):
    stored = store(folder, "c.zip", make_zip(cornell + [("__MACOSX/._cornell.obj", b"\0\5"), (".DS_Store", b"\0")]))
    assert stored.scene_file == folder / "cornell.obj"
    assert sorted(tree(folder)) == ["cornell.mtl", "cornell.obj", "cornell.rt.json"]


def test_files_of_other_types_are_left_out_and_named(folder, cornell):
    inner = make_zip([("other.obj", cornell[0][1])])
    extra = [("more.zip", inner), ("run.exe", b"MZ"), ("docs/index.html", b"<script>"), ("tex/wood.png", b"png")]
    stored = store(folder, "c.zip", make_zip(cornell + extra))
    assert stored.scene_file == folder / "cornell.obj"
    assert sorted(stored.left_out) == ["docs/index.html", "more.zip", "run.exe"]
    assert not (folder / "more.zip").exists() and not (folder / "other.obj").exists()
    assert not (folder / "run.exe").exists() and (folder / "tex" / "wood.png").exists()


def test_filename_loses_its_folders_and_odd_characters(folder, cornell):
    assert store(folder, "../../etc/passwd.obj", cornell[0][1]).scene_file == folder / "passwd.obj"
    for child in folder.iterdir():
        child.unlink()
    assert store(folder, "C:\\Users\\me\\.my*scene?.OBJ", cornell[0][1]).scene_file == folder / "my_scene_.obj"


def test_upload_of_exactly_max_bytes_is_accepted(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    assert store(folder, "b.glb", data, max_bytes=len(data)).size_bytes == len(data)


# --- size limits stop early --------------------------------------------------------------------

class GeneratorStream:
    """A file-like upload fed by a generator, counting what was pulled from it."""

    def __init__(self, chunks):
        self._chunks, self._buffer, self.exhausted, self.returned = iter(chunks), b"", False, 0

    def read(self, n=-1):
        while n < 0 or len(self._buffer) < n:
            try:
                self._buffer += next(self._chunks)
            except StopIteration:
                self.exhausted = True
                break
        n = len(self._buffer) if n < 0 else n
        out, self._buffer = self._buffer[:n], self._buffer[n:]
        self.returned += len(out)
        return out


def test_size_limit_stops_reading_the_stream_early(folder):
    produced = []

    def chunks():  # 100 MB, one megabyte at a time
        for i in range(100):
            produced.append(i)
            yield b"v 0 0 0\n" * (MB // 8)

    stream = GeneratorStream(chunks())
    with pytest.raises(UploadError) as caught:
        store_upload("big.obj", stream, folder, **{**LIMITS, "max_bytes": 3 * MB})
    assert http_status(caught.value) == 413 and "3145728" in str(caught.value)
    assert not stream.exhausted and len(produced) <= 4
    assert stream.returned == 3 * MB + 1  # not one byte more than needed to know
    assert list(folder.iterdir()) == []


def test_upload_one_byte_over_max_bytes_is_413(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    refused(folder, "b.glb", data, 413, "larger than the limit", max_bytes=len(data) - 1)


# --- zip safety --------------------------------------------------------------------------------

@pytest.mark.parametrize("name, words", [
    ("../evil.txt", "climbs out"),
    ("/etc/x", "absolute path"),
    ("a/../../b", "climbs out"),
    ("a\\..\\..\\evil.txt", "climbs out"),
    ("C:/evil.txt", "absolute path"),
], ids=["parent", "absolute", "climb-after-descent", "backslashes", "drive-letter"])
def test_zip_slip_entry_is_refused(folder, cornell, name, words):
    existed = Path("/etc/x").exists()
    refused(folder, "c.zip", make_zip(cornell + [(name, b"owned")]), 400, words)
    assert Path("/etc/x").exists() == existed


def test_symlink_entry_is_refused(folder, cornell):
    link = zipfile.ZipInfo("cornell.mtl")
    link.create_system, link.external_attr = 3, (stat.S_IFLNK | 0o777) << 16
    refused(folder, "c.zip", make_zip([cornell[0], (link, b"/etc/passwd")]), 400, "symbolic link")


def bomb(uncompressed=50 * MB) -> bytes:
    return make_zip([("scene.obj", b"v 0 0 0\n"), ("zeros.bin", bytes(uncompressed))])


@pytest.fixture
def peak(monkeypatch):
    """What the folder held just before a refusal emptied it."""
    sizes = []
    empty = uploads._empty

    def measured(folder):
        sizes.append(sum(tree(folder).values()))
        empty(folder)

    monkeypatch.setattr(uploads, "_empty", measured)
    return sizes


def test_zip_bomb_declaring_its_size_is_refused_before_unpacking(folder, peak):
    data = bomb()
    assert len(data) < MB
    refused(folder, "b.zip", data, 413, "unpacks to 52428808 bytes", max_unpacked_bytes=MB)
    assert peak[0] <= len(data)  # only the spooled zip: nothing was unpacked


def test_zip_bomb_lying_about_its_size_unpacks_no_more_than_it_declared(folder, peak):
    data = patch_headers(bomb(), uncompressed_size=1000)
    refused(folder, "b.zip", data, 400, "damaged", max_unpacked_bytes=MB)
    assert peak[0] <= len(data) + MB


def test_unpacked_bytes_are_counted_even_if_zipfile_ignored_declared_sizes(folder, peak, monkeypatch):
    """Our own count, not zipfile's trust in the declared size, stops the bomb."""
    opened = zipfile.ZipExtFile.__init__
    patched = []

    def without_declared_limit(self, *args, **kwargs):
        opened(self, *args, **kwargs)
        if "_left" in vars(self):
            self._left, self._expected_crc = 1 << 62, None  # read on to the end, no CRC check
            patched.append(self)

    monkeypatch.setattr(zipfile.ZipExtFile, "__init__", without_declared_limit)
    data = patch_headers(bomb(), uncompressed_size=1000)
    with zipfile.ZipFile(io.BytesIO(data)) as probe, probe.open("zeros.bin"):
        if not patched:
            pytest.skip("zipfile.ZipExtFile keeps the declared size elsewhere in this Python")
    refused(folder, "b.zip", data, 413, f"more than the limit of {MB} bytes", max_unpacked_bytes=MB)
    assert peak[0] <= len(data) + MB


def test_bzip2_entries_are_refused_as_their_decompression_is_unbounded(folder, cornell):
    refused(folder, "c.zip", make_zip(cornell, zipfile.ZIP_BZIP2), 400, "compression method")


def test_too_many_files_is_413(folder, cornell):
    refused(folder, "c.zip", make_zip(cornell + [("tex.png", b"x")]), 413, "4 entries, more than the limit of 3",
            max_files=3)


@pytest.mark.parametrize("second", ["cornell.mtl", "CORNELL.MTL", "./cornell.mtl"])
def test_duplicate_names_are_refused_whatever_their_case(folder, cornell, second):
    refused(folder, "c.zip", make_zip(cornell + [(second, b"newmtl x\n")]), 400, "twice")


def test_name_used_as_file_and_folder_is_refused(folder, cornell):
    data = make_zip(cornell + [("tex", b"x"), ("TEX/a.png", b"y")])
    refused(folder, "c.zip", data, 400, "both a file and a folder")


def test_encrypted_entry_is_refused(folder, cornell):
    refused(folder, "c.zip", patch_headers(make_zip(cornell), flag_bits=0x1), 400, "encrypted")


def test_two_scenes_are_refused_naming_both(folder, cornell):
    data = make_zip([("a.gltf", b'{"asset": {"version": "2.0"}}'), ("b.obj", cornell[0][1])])
    refused(folder, "two.zip", data, 400, "the zip holds several scenes: a.gltf, b.obj; upload one at a time")


def test_zip_without_a_scene_is_refused(folder, cornell):
    refused(folder, "c.zip", make_zip(cornell[1:]), 400, "no scene file")


@pytest.mark.parametrize("cut", [None, 0.5, 0.9], ids=["not-a-zip", "half", "nine-tenths"])
def test_corrupt_or_truncated_zip_is_400(folder, cornell, cut):
    data = make_zip(cornell)
    data = os.urandom(4000) if cut is None else data[: int(len(data) * cut)]
    refused(folder, "c.zip", data, 400, "the zip is damaged or truncated")


def test_damaged_data_inside_a_zip_is_400(folder, cornell):
    data = bytearray(make_zip(cornell))
    data[100:140] = bytes(40)  # inside cornell.obj's deflate stream
    refused(folder, "c.zip", bytes(data), 400, "the zip is damaged or truncated")


# --- the scene file itself ---------------------------------------------------------------------

def test_glb_with_wrong_magic_is_refused(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    refused(folder, "b.glb", b"glTX" + data[4:], 400, "not a GLB file")


def test_glb_of_version_1_is_refused(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    refused(folder, "b.glb", data[:4] + struct.pack("<I", 1) + data[8:], 400, "version 1")


def test_glb_length_mismatch_is_refused(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    refused(folder, "b.glb", data[:-100], 400, f"declares {len(data)} bytes but holds {len(data) - 100}")


def test_glb_inside_a_zip_gets_the_same_checks(folder, scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    refused(folder, "b.zip", make_zip([("bunny.glb", data[:-4])]), 400, "'bunny.glb' declares")


@pytest.mark.parametrize("text, words", [
    (b"{not json", "not valid JSON"),
    (b'["asset"]', "not a glTF file"),
    (b'{"scenes": []}', "not a glTF file"),
    (b"[" * 100000 + b"]" * 100000, "not valid JSON"),
], ids=["not-json", "array", "no-asset", "deeply-nested"])
def test_gltf_that_is_not_a_gltf_json_object_is_refused(folder, text, words):
    refused(folder, "s.gltf", text, 400, words)


def test_binary_obj_is_refused(folder):
    refused(folder, "s.obj", b"v 0 0 0\n\0\0\0", 400, "not a text file")


def test_empty_file_is_refused(folder):
    refused(folder, "s.obj", b"", 400, "empty")


@pytest.mark.parametrize("filename, words", [
    ("", "no name"),
    ("   ", "no name"),
    ("uploads/", "no name"),
    ("sc\x00ene.glb", "control characters"),
    ("sc\nene.glb", "control characters"),
    ("x" * 252 + ".glb", "longer than 255 bytes"),
    ("é" * 126 + ".glb", "longer than 255 bytes"),  # 256 bytes in UTF-8, 130 characters
    ("\udcff.glb", "not valid text"),
], ids=["empty", "blank", "folder-only", "nul", "newline", "256-bytes", "256-utf8-bytes", "surrogate"])
def test_bad_filename_is_400(folder, scenes_dir, filename, words):
    refused(folder, filename, (scenes_dir / "bunny.glb").read_bytes(), 400, words)


@pytest.mark.parametrize("filename, shown", [
    ("scene.png", "'.png'"), ("cornell.rt.json", "'.json'"), ("scene", "'scene' has no extension"),
])
def test_unsupported_type_is_415_naming_it_and_the_accepted_ones(folder, filename, shown):
    error = refused(folder, filename, b"data", 415, shown)
    assert all(kind in str(error) for kind in (".glb", ".gltf", ".obj", ".zip"))


def test_a_folder_that_is_not_empty_is_a_programming_error(folder):
    (folder / "theirs.txt").write_text("keep")
    with pytest.raises(RuntimeError):
        store(folder, "s.obj", b"v 0 0 0\n")
    assert (folder / "theirs.txt").read_text() == "keep"
