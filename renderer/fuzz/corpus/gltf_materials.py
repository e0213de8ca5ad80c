"""Hostile glTF files about images, textures, samplers and materials.

A broken image is mostly a warning (the texture is ignored) while a broken
reference is an error; these cases pin down which is which, and where an image
header claiming a huge size stops being accepted.
"""

from __future__ import annotations

from .bases import PNG, Corpus, data_uri, dump, png_header, textured_doc


def material_cases(c: Corpus) -> None:
    # Images: malformed data: URIs, lying headers, views out of their buffer.
    for name, image, expect, mentions in [
        ("data_uri_junk", {"uri": "data:image/png;base64,!!!!"}, "error", "malformed data: URI"),
        ("data_uri_empty", {"uri": "data:image/png;base64,"}, "error", "it holds no data"),
        ("data_uri_png", {"uri": data_uri(PNG, "image/png")}, "loads", ""),
        # Modernizr's 1x1 lossless WebP: tinygltf 2.7 does not decode this media type; the loader relabels it.
        ("data_uri_webp", {"uri": "data:image/webp;base64,UklGRhoAAABXRUJQVlA4TA0AAAAvAAAAEAcQERGIiP4HAA=="},
         "loads", ""),
        ("data_uri_webp_broken", {"uri": "data:image/webp;base64,AAAA"}, "loads", "texture ignored"),
        ("data_uri_not_image", {"uri": data_uri(PNG)}, "error", "an image's must be an image type"),
        ("data_uri_plain", {"uri": "data:image/png,rawbytes"}, "error", "data: URI"),
        ("not_an_image", {"uri": "buffer.bin"}, "loads", "is not a PNG, JPEG, BMP, TGA or WebP image"),
        # 768 MiB of 8-bit texels and mips: an RGB image of 14189x14189 fits, one texel more per side not.
        ("huge_header", {"uri": data_uri(png_header(16000, 16000), "image/png")}, "error", "texels"),
        ("huge_header_14190", {"uri": data_uri(png_header(14190, 14190), "image/png")}, "error", "texels"),
        ("huge_header_14189", {"uri": data_uri(png_header(14189, 14189), "image/png")}, "loads", "texture ignored"),
        # Beyond what stb_image decodes at all: a broken image, only a warning.
        ("huge_header_65536", {"uri": data_uri(png_header(65536, 65536), "image/png")}, "loads", "texture ignored"),
        ("huge_header_100000", {"uri": data_uri(png_header(100000, 100000), "image/png")}, "loads",
         "texture ignored"),
        ("zero_header", {"uri": data_uri(png_header(0, 0), "image/png")}, "loads", "texture ignored"),
        ("truncated_png", {"uri": data_uri(PNG[:40], "image/png")}, "loads", "texture ignored"),
        ("view_missing", {"bufferView": 9, "mimeType": "image/png"}, "error", "images[0].bufferView"),
        ("view_negative", {"bufferView": -1, "mimeType": "image/png"}, "any", ""),
        ("view_huge", {"bufferView": 2**64 - 1, "mimeType": "image/png"}, "error", "images[0].bufferView"),
        ("uri_and_view", {"bufferView": 0, "uri": "image.png"}, "any", ""),
        ("no_source", {}, "any", ""),
    ]:
        c.add(f"gltf_image_{name}.gltf", dump(textured_doc(image)), expect, mentions)
    for name, fields, mentions in [
        ("past_buffer", {"byteOffset": 100, "byteLength": 100}, "does not lie inside"),
        ("huge_length", {"byteOffset": 0, "byteLength": 2**64 - 1}, "does not lie inside"),
        ("empty", {"byteOffset": 0, "byteLength": 0}, "does not lie inside"),
    ]:
        d = textured_doc({"bufferView": 4, "mimeType": "image/png"})
        d["bufferViews"].append({"buffer": 0, **fields})
        c.add(f"gltf_image_view_{name}.gltf", dump(d), "error", mentions)
    for name, mutate, expect, mentions in [
        ("texture_missing", lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(index=5),
         "error", "refers to texture 5"),
        ("texture_negative", lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(
            index=-2), "any", ""),
        ("texcoord_9", lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(texCoord=9),
         "loads", "only TEXCOORD_0 and TEXCOORD_1 are read"),
        ("source_missing", lambda d: d["textures"][0].update(source=3), "error", "refers to image 3"),
        ("sampler_missing", lambda d: d["textures"][0].update(sampler=2), "error", "refers to sampler 2"),
        ("wrap_unknown", lambda d: d.update(samplers=[{"wrapS": 1}]) or d["textures"][0].update(sampler=0),
         "error", "unknown wrap mode 1"),
        ("texcoord_count", lambda d: d["accessors"][3].update(count=2), "error", "has 2 elements, but POSITION has 3"),
        ("texcoord_bytes", lambda d: d["accessors"][3].update(componentType=5121), "loads", ""),
        ("texcoord_int", lambda d: d["accessors"][3].update(componentType=5124), "error",
         "unsupported component type INT"),
        ("material_missing", lambda d: d["meshes"][0]["primitives"][0].update(material=4), "error",
         "refers to material 4"),
        ("material_negative", lambda d: d["meshes"][0]["primitives"][0].update(material=-9), "error", ""),
        ("base_color_3", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(baseColorFactor=[1, 1, 1]),
         "any", ""),  # tinygltf keeps its default for a factor of the wrong size
        ("base_color_huge", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(
            baseColorFactor=[1e308, -1e308, 1, 1]), "loads", ""),
        ("metallic_string", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(metallicFactor="1"),
         "any", ""),
        ("ior_zero", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": {"ior": 0}}),
         "error", "KHR_materials_ior.ior"),
        ("ior_huge", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": {"ior": 1e300}}),
         "error", "KHR_materials_ior.ior is 1e+300, expected"),
        ("ior_string", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": {"ior": "1.5"}}),
         "error", "KHR_materials_ior.ior"),
        ("transmission_string", lambda d: d["materials"][0].update(
            extensions={"KHR_materials_transmission": {"transmissionFactor": "0.5"}}), "error", "transmissionFactor"),
        ("extension_not_object", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": 3}), "any", ""),
    ]:
        d = textured_doc({"uri": "image.png"})
        mutate(d)
        c.add(f"gltf_material_{name}.gltf", dump(d), expect, mentions)
