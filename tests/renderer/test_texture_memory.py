"""What textures cost once loaded: five 4096x4096 RGBA maps through rtcore.

8-bit texels with their mip chains take 4/3 of the images' bytes; the linear
float RGB texels of before took 12 bytes a texel, 960 MiB for these five (over
the scene budget, which refused them).
"""
import json
import resource

import numpy as np
from PIL import Image

import rtcore

SIZE = 4096
MAPS = 5


def rss_bytes() -> int:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def write_maps(folder):
    # A pattern PNG compresses well (so the test writes quickly) that still
    # varies in every channel; each map its own.
    y, x = np.mgrid[0:SIZE, 0:SIZE].astype(np.uint32)
    for k in range(MAPS):
        rgba = np.stack([(x + 37 * k) & 255, (y * 3 + k) & 255, ((x ^ y) + k) & 255, 128 + ((x >> 5) & 127)], axis=-1)
        Image.fromarray(rgba.astype(np.uint8), "RGBA").save(folder / f"map{k}.png", compress_level=1)


def write_gltf(folder):
    positions = np.array([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0], np.float32)
    uvs = np.array([0, 1, 1, 1, 0, 0, 1, 0], np.float32)
    indices = np.array([0, 1, 2, 1, 3, 2, 0, 1, 2], np.uint32)
    data = positions.tobytes() + uvs.tobytes() + indices.tobytes()
    (folder / "maps.bin").write_bytes(data)
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "maps.bin", "byteLength": len(data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 36},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 3, "type": "SCALAR"},
            {"bufferView": 2, "byteOffset": 12, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
        "images": [{"uri": f"map{k}.png"} for k in range(MAPS)],
        "textures": [{"source": k} for k in range(MAPS)],
        # Base colour, metallic-roughness, occlusion and emission on one
        # material, another base colour on a second: five maps read.
        "materials": [
            {
                "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}},
                "occlusionTexture": {"index": 2},
                "emissiveTexture": {"index": 3},
                "emissiveFactor": [1, 1, 1],
            },
            {"pbrMetallicRoughness": {"baseColorTexture": {"index": 4}}},
        ],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
            {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 3, "material": 1},
        ]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }
    path = folder / "maps.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_five_4k_maps_cost_what_their_8_bit_texels_and_mips_do(tmp_path):
    write_maps(tmp_path)
    path = write_gltf(tmp_path)
    before = rss_bytes()
    scene = rtcore.Scene.load(str(path))
    growth = rss_bytes() - before
    texels = MAPS * SIZE * SIZE * 4
    print(f"\n{MAPS} textures of {SIZE}x{SIZE} RGBA: {scene.texture_bytes / 2**20:.1f} MiB with mips "
          f"({scene.texture_bytes / texels:.3f} of their 8-bit texels, {texels / 2**20:.0f} MiB); "
          f"resident memory grew by {growth / 2**20:.1f} MiB; peak RSS of the process "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10:.0f} MiB; "
          f"as linear float RGB they were {MAPS * SIZE * SIZE * 12 / 2**20:.0f} MiB without mips")
    assert scene.texture_bytes <= 1.45 * texels
    assert scene.texture_bytes >= texels  # level 0 is all there
    # What is resident is the textures and little else: the decoders' buffers are gone.
    assert growth <= 1.45 * texels + 64 * 2**20
