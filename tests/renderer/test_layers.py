"""renderer/src is layered: a file includes only its own folder and the folders
below it, in the order CMakeLists.txt lists them (RT_LAYERS), so a reader can
tell where loading ends and rendering starts, and the fuzz build can take the
loaders without the renderer."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "renderer" / "src"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def layers() -> list[str]:
    cmake = (ROOT / "renderer" / "CMakeLists.txt").read_text()
    return re.search(r"set\(RT_LAYERS ([^)]*)\)", cmake).group(1).split()


def upward_includes(src: Path, order: list[str]) -> list[str]:
    rank = {layer: i for i, layer in enumerate(order)}
    found = []
    for path in sorted(src.rglob("*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        layer = path.relative_to(src).parts[0]
        for name in INCLUDE.findall(path.read_text()):
            target = name.split("/")[0]
            if target == "rt":  # code generated from proto/, below every layer
                continue
            if target not in rank:
                found.append(f"{path.relative_to(src)} includes {name}, which is in no layer")
            elif rank[target] > rank[layer]:
                found.append(f"{path.relative_to(src)} ({layer}) includes {name} ({target}, above it)")
    return found


def test_every_source_is_in_a_layer_folder():
    order = layers()
    assert order[0] == "util"
    stray = [p.name for p in SRC.iterdir() if p.is_file()]
    assert stray == [], f"files outside the layer folders: {stray}"
    assert sorted(p.name for p in SRC.iterdir() if p.is_dir()) == sorted(order)


def test_no_include_points_upwards():
    assert upward_includes(SRC, layers()) == []


def test_an_upward_include_is_reported(tmp_path):
    (tmp_path / "util").mkdir()
    (tmp_path / "load").mkdir()
    (tmp_path / "util" / "a.cpp").write_text('#include "load/loader.h"\n#include "rt/job.pb.h"\n')
    (tmp_path / "load" / "b.cpp").write_text('#include "util/a.h"\n#include "nowhere.h"\n')
    assert upward_includes(tmp_path, ["util", "load"]) == [
        "load/b.cpp includes nowhere.h, which is in no layer",
        "util/a.cpp (util) includes load/loader.h (load, above it)",
    ]
