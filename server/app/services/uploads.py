"""One uploaded file into a scene folder on disk, everything hostile until checked.

Checks that live here, before any scene parser runs:
- the upload's name (folders stripped, no control characters, at most 255 bytes)
  and type (.glb, .gltf, .obj, or a .zip holding one of them);
- its size, counted while streaming, and its SHA-256 (the workers' cache key);
- that the scene file is what its extension says: the GLB header (magic, version
  2, declared length), a .gltf that is a JSON object with an "asset", an .obj
  without NUL bytes;
- for a zip: each entry's path (no absolute paths, drive letters or '..', with
  backslashes read as folders), type (no symlinks or devices), encryption,
  compression method; the entry count, duplicates (also case-insensitively),
  the declared and the actually unpacked size, and exactly one scene file.

Checks that live in the renderer's loader (rtcore.Scene.load, whose ValueError
the caller turns into an UploadError): everything inside the scene files, and every
reference they make (buffers, images, .mtl, textures, the .rt.json sidecar),
which must stay inside the scene file's own folder: no URLs, absolute paths,
'..' or symbolic links leading out.
"""
import hashlib
import json
import re
import shutil
import stat
import unicodedata
import zipfile
import zlib
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Iterator

from .errors import Refused, TooLarge, UnsupportedType

SCENE_FORMATS = ("glb", "gltf", "obj")
# What a scene's folder may hold: scene files, glTF buffers, OBJ materials, the
# .rt.json sidecar, and the textures the renderer decodes. Other files in a zip
# are left out (and named in the scene's warnings).
KEPT_SUFFIXES = frozenset(SCENE_FORMATS + ("bin", "mtl", "json", "png", "jpg", "jpeg", "bmp", "tga", "webp"))
_CHUNK = 1 << 20
_MAX_NAME_BYTES = 255
_MAX_PATH_BYTES = 1024
_CONTROL = re.compile(r"[\x00-\x1f\x7f]")
_DRIVE = re.compile(r"^[A-Za-z]:")
# zipfile hands bzip2 and LZMA data to the decompressor with no output limit, so
# one read of a few compressed bytes can unpack to gigabytes in memory (100 MB of
# zeros is 113 bytes of bzip2). Deflate honours a limit; stored needs none.
_SAFE_METHODS = (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED)


class UploadError(Refused):
    """A refused upload: bad content; str(e) names the problem in plain words for the user."""


class UploadTooLarge(UploadError, TooLarge):
    """An upload, or what a zip unpacks to, over a size or count limit."""


class UploadTypeRefused(UploadError, UnsupportedType):
    """A file of a type that is not a scene or a zip of one."""


@dataclass(frozen=True)
class StoredUpload:
    folder: Path
    scene_file: Path  # inside folder; in a subfolder of it if the zip had it there
    format: str  # "glb" | "gltf" | "obj"
    size_bytes: int  # bytes received
    sha256: str  # hex digest of the bytes received (of the zip, for a zip)
    left_out: tuple[str, ...] = ()  # zip entries of other types, not unpacked


def store_upload(filename: str, stream: BinaryIO, folder: Path, *, max_bytes: int,
                 max_unpacked_bytes: int, max_files: int) -> StoredUpload:
    """Streams `stream` into the empty `folder` and returns where the scene is.

    Raises UploadError for anything refused; `folder` is then left empty again.
    """
    if any(folder.iterdir()):  # the cleanup below must never touch the caller's files
        raise RuntimeError(f"store_upload needs a fresh empty folder, and {folder} is not")
    name, extension = _sanitized_name(filename)
    try:
        if extension == "zip":
            spool = folder / ".upload.zip.part"
            size, sha256 = _receive(stream, spool, max_bytes)
            with open(spool, "rb") as spooled:
                spool.unlink()  # still readable while open; no entry can clash with it, nor refusal leave it
                scene_file, left_out = _extract_zip(spooled, folder, max_unpacked_bytes, max_files)
        else:
            left_out = ()
            scene_file = folder / name
            size, sha256 = _receive(stream, scene_file, max_bytes)
        scene_format = scene_file.suffix[1:].lower()
        _check_scene_file(scene_file, scene_format)
        return StoredUpload(folder, scene_file, scene_format, size, sha256, left_out)
    except BaseException:
        _empty(folder)
        raise


def _shown(text: str, limit: int = 120) -> str:
    """A hostile name, quoted and safe to print: control characters become '?'."""
    clean = _CONTROL.sub("?", text)
    return "'" + (clean[:limit] + "..." if len(clean) > limit else clean) + "'"


def _sanitized_name(filename: str) -> tuple[str, str]:
    """The upload's name without folders and odd characters, and its lowercased extension."""
    name = filename.replace("\\", "/").rsplit("/", 1)[-1].strip()
    if not name:
        raise UploadError("the file has no name")
    if _CONTROL.search(name):
        raise UploadError(f"the file name {_shown(name)} contains control characters")
    try:  # lone surrogates could not even be sent back in the error message
        too_long = len(name.encode("utf-8")) > _MAX_NAME_BYTES
    except UnicodeEncodeError:
        raise UploadError("the file name is not valid text") from None
    if too_long:
        raise UploadError(f"the file name is longer than {_MAX_NAME_BYTES} bytes")
    stem, dot, extension = name.rpartition(".")
    extension = extension.lower()
    if not dot or extension not in (*SCENE_FORMATS, "zip"):
        what = f"{_shown('.' + extension)} files are" if dot else f"{_shown(name)} has no extension and is"
        raise UploadTypeRefused(f"{what} not accepted: upload a .glb, .gltf or .obj scene, "
                                "or a .zip holding one scene and its files")
    # Letters, digits and a few harmless marks; no leading dot (a hidden file).
    stem = re.sub(r"[^\w .()+-]", "_", stem).lstrip(". ") or "scene"
    return f"{stem}.{extension}", extension


def _receive(stream: BinaryIO, target: Path, max_bytes: int) -> tuple[int, str]:
    """Copies the stream to `target` in chunks, reading at most one byte past the limit."""
    digest, size = hashlib.sha256(), 0
    with open(target, "xb") as out:
        while chunk := stream.read(min(_CHUNK, max_bytes + 1 - size)):
            size += len(chunk)
            if size > max_bytes:
                raise UploadTooLarge(f"the upload is larger than the limit of {max_bytes} bytes")
            digest.update(chunk)
            out.write(chunk)
    if size == 0:
        raise UploadError("the file is empty")
    return size, digest.hexdigest()


@contextmanager
def _reading_zip() -> Iterator[None]:
    """zipfile reports a damaged archive through many exception types: each is a 400.
    (It raises NotImplementedError for a compression method it does not know,
    which in a hostile upload is as good as damage.)"""
    try:
        yield
    except UploadError:
        raise
    except (zipfile.BadZipFile, zlib.error, EOFError, OSError, ValueError, NotImplementedError) as e:
        raise UploadError(f"the zip is damaged or truncated: {e}") from e


def _entry_parts(info: zipfile.ZipInfo) -> tuple[tuple[str, ...], bool]:
    """The entry's path as safe components and whether it is a folder, or UploadError."""
    raw = info.orig_filename  # zipfile's .filename silently cuts at a NUL
    what = f"the zip entry {_shown(raw)}"
    if _CONTROL.search(raw):
        raise UploadError(f"{what} has control characters in its name")
    name = raw.replace("\\", "/")  # some Windows tools write backslashes: read them as folders
    if name.startswith("/") or _DRIVE.match(name):
        raise UploadError(f"{what} has an absolute path")
    parts = tuple(part for part in name.split("/") if part not in ("", "."))
    if ".." in parts:
        raise UploadError(f"{what} climbs out of its folder with '..'")
    if len(name.encode()) > _MAX_PATH_BYTES or any(len(p.encode()) > _MAX_NAME_BYTES for p in parts):
        raise UploadError(f"{what} has a name too long to store")
    mode = info.external_attr >> 16  # the Unix mode, when the zip was made on Unix
    if stat.S_ISLNK(mode):
        raise UploadError(f"{what} is a symbolic link")
    if stat.S_IFMT(mode) not in (0, stat.S_IFREG, stat.S_IFDIR):
        raise UploadError(f"{what} is not a regular file")
    if info.flag_bits & 0x1:
        raise UploadError(f"{what} is encrypted")
    if info.compress_type not in _SAFE_METHODS:
        raise UploadError(f"{what} uses a compression method we do not unpack (only stored and deflate)")
    return parts, name.endswith("/") or stat.S_ISDIR(mode)


def _is_junk(parts: tuple[str, ...]) -> bool:
    """macOS Finder adds __MACOSX/._scene.obj and .DS_Store: not the user's files."""
    return parts[0] == "__MACOSX" or parts[-1] == ".DS_Store" or parts[-1].startswith("._")


def _extract_zip(spooled: BinaryIO, folder: Path, max_unpacked_bytes: int,
                 max_files: int) -> tuple[Path, tuple[str, ...]]:
    """Checks every entry, then unpacks the zip into `folder`; returns the scene
    file and the entries left out for their type."""
    with _reading_zip():
        archive = zipfile.ZipFile(spooled)  # holds no resource of its own: closing `spooled` is enough
    infos = archive.infolist()
    if len(infos) > max_files:
        raise UploadTooLarge(f"the zip holds {len(infos)} entries, more than the limit of {max_files}")
    declared = sum(info.file_size for info in infos)
    if declared > max_unpacked_bytes:
        raise UploadTooLarge(f"the zip unpacks to {declared} bytes, more than the limit of {max_unpacked_bytes}")
    entries, files, dirs = [], set(), set()
    for info in infos:
        parts, is_dir = _entry_parts(info)
        if not parts or _is_junk(parts):
            continue
        # NFC + casefold: names that a case-insensitive or normalising file system would merge.
        key = tuple(unicodedata.normalize("NFC", part).casefold() for part in parts)
        dirs.update(key[:i] for i in range(1, len(key)))
        if is_dir:
            dirs.add(key)
        elif key in files:
            raise UploadError(f"the zip holds {_shown('/'.join(parts))} twice (perhaps in another case)")
        else:
            files.add(key)
        entries.append((info, parts, is_dir))
    if clash := files & dirs:
        raise UploadError(f"the zip uses {_shown('/'.join(min(clash)))} as both a file and a folder")

    scenes = [parts for _, parts, is_dir in entries
              if not is_dir and parts[-1].rpartition(".")[2].lower() in SCENE_FORMATS]
    if not scenes:
        raise UploadError("the zip holds no scene file (.gltf, .glb or .obj)")
    if len(scenes) > 1:
        shown = ", ".join("/".join(parts) for parts in scenes[:5]) + (", ..." if len(scenes) > 5 else "")
        raise UploadError(f"the zip holds several scenes: {_shown(shown, 400)[1:-1]}; upload one at a time")

    left_out = tuple("/".join(parts) for _, parts, is_dir in entries
                     if not is_dir and parts[-1].rpartition(".")[2].lower() not in KEPT_SUFFIXES)
    entries = [(info, parts, is_dir) for info, parts, is_dir in entries
               if is_dir or parts[-1].rpartition(".")[2].lower() in KEPT_SUFFIXES]
    root = folder.resolve()
    budget = max_unpacked_bytes  # spent on the bytes actually unpacked, not on the declared sizes
    for info, parts, is_dir in entries:
        target = folder.joinpath(*parts)
        if not target.resolve().is_relative_to(root):  # belt and braces: the checks above keep it inside
            raise UploadError(f"the zip entry {_shown(info.orig_filename)} leads outside its folder")
        (target if is_dir else target.parent).mkdir(parents=True, exist_ok=True)
        if not is_dir:
            budget = _unpack(archive, info, target, budget, max_unpacked_bytes)
    return folder.joinpath(*scenes[0]), left_out


def _unpack(archive: zipfile.ZipFile, info: zipfile.ZipInfo, target: Path, budget: int, limit: int) -> int:
    """Copies one entry to `target` and returns the budget left, refusing when it runs out.

    zipfile itself stops at the declared size, but a zip bomb lies about its sizes:
    the count here does not depend on zipfile getting that right.
    """
    with _reading_zip():
        source = archive.open(info)
    with source, open(target, "xb") as out:
        while True:
            with _reading_zip():
                chunk = source.read(min(_CHUNK, budget + 1))
            if not chunk:
                return budget
            budget -= len(chunk)
            if budget < 0:
                raise UploadTooLarge(f"the zip unpacks to more than the limit of {limit} bytes")
            out.write(chunk)


def _check_scene_file(path: Path, scene_format: str) -> None:
    """Is the scene file what its extension says? The loader checks the rest."""
    what, size = _shown(path.name), path.stat().st_size
    if scene_format == "glb":
        with open(path, "rb") as f:
            header = f.read(12)
        if len(header) < 12 or header[:4] != b"glTF":
            raise UploadError(f"{what} is not a GLB file: it does not start with 'glTF'")
        version, length = int.from_bytes(header[4:8], "little"), int.from_bytes(header[8:12], "little")
        if version != 2:
            raise UploadError(f"{what} is GLB version {version}; only glTF 2.0 is supported")
        if length != size:
            raise UploadError(f"{what} declares {length} bytes but holds {size}: truncated or damaged")
    elif scene_format == "gltf":
        try:
            document = json.loads(path.read_bytes())
        except (ValueError, RecursionError) as e:  # JSONDecodeError, UnicodeDecodeError; nesting too deep
            raise UploadError(f"{what} is not valid JSON: {str(e)[:200]}") from None
        if not isinstance(document, dict) or "asset" not in document:
            raise UploadError(f"{what} is not a glTF file: not a JSON object with an \"asset\"")
    elif scene_format == "obj":
        with open(path, "rb") as f:
            while chunk := f.read(_CHUNK):
                if b"\0" in chunk:
                    raise UploadError(f"{what} is not a text file, as an OBJ scene must be")


def _empty(folder: Path) -> None:
    """Removes all that store_upload wrote: files and folders, never a symlink's target."""
    for child in folder.iterdir():
        if child.is_dir() and not child.is_symlink():
            shutil.rmtree(child)
        else:
            child.unlink()
