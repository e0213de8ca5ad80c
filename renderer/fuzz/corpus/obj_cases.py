"""Hostile OBJ files and their MTL material libraries.

tinyobjloader is lenient (a number it cannot parse reads as 0), so the
loader's own checks are what these cases exercise: indices out of range,
numbers beyond float, material libraries outside the folder, names that are
not UTF-8, lines that never end.
"""

from __future__ import annotations

import math

from .bases import MTL, OBJ, TRI, Corpus, obj, truncations

def obj_cases(c: Corpus) -> None:
    c.companion("base.mtl", MTL)
    c.add("obj_valid.obj", OBJ, "loads")

    for n in truncations(len(OBJ), 40):
        c.add(f"obj_truncated_{n:04d}.obj", OBJ[:n], "any")
    for n in truncations(len(MTL), 24):
        c.companion(f"obj_truncated_mtl_{n:04d}.mtl", MTL[:n])
        c.add(f"obj_truncated_mtl_{n:04d}.obj", OBJ.replace(b"base.mtl", f"obj_truncated_mtl_{n:04d}.mtl".encode()),
              "any")

    def case(name: str, data: bytes, expect: str = "error", mentions: str = "") -> None:
        c.add(f"obj_{name}.obj", data, expect, mentions)

    # Indices: huge, negative, zero, of the wrong kind.
    for name, face, mentions in [
        ("index_past_end", "f 1 2 4", "vertex index is out of range (3 vertices)"),
        ("index_int_max", "f 1 2 2147483647", "vertex index is out of range"),
        ("index_int_overflow", "f 1 2 2147483648", ""),
        ("index_huge", "f 1 2 99999999999999999999999", ""),
        ("index_negative_past_start", "f 1 2 -4", "vertex index is out of range"),
        ("index_int_min", "f 1 2 -2147483648", ""),
        ("index_negative_huge", "f -99999999999999999999 1 2", ""),
        ("index_zero", "f 1 2 0", "zero value for face index. line 4.)"),
        ("normal_past_end", "f 1//1 2//1 3//2", "normal index is out of range"),
        ("normal_int_min", "f 1//-2147483648 2//1 3//1", ""),
        ("texcoord_past_end", "f 1/2 2/1 3/1", "texture coordinate index is out of range"),
        ("texcoord_huge", "f 1/2147483647 2/1 3/1", "texture coordinate index is out of range"),
        ("index_not_number", "f 1 2 x", ""),
        ("index_empty_parts", "f 1/ 2// 3///", ""),
        ("face_two_corners", "f 1 2", ""),
        ("face_one_corner", "f 1", ""),  # tinyobjloader's warning "Degenerated face found\n." (no "." warning)
        ("face_no_corner", "f", ""),
    ]:
        lines = TRI + (("vn 0 0 1",) if "normal" in name else ()) + (("vt 0 0",) if "texcoord" in name else ())
        expect = "error" if mentions else "any"
        if name in ("face_two_corners", "face_one_corner"):
            expect, mentions = "loads", "Degenerated face found"
        case(name, obj(*lines, face, mtllib=None), expect, mentions)
    for corners in (256, 258, 300, 1000):
        verts = [f"v {math.cos(i * 0.01):.6f} {math.sin(i * 0.01):.6f} 0" for i in range(corners)]
        face = "f " + " ".join(str(i + 1) for i in range(corners))
        case(f"face_{corners}_corners", obj(*verts, face, mtllib=None), "error", "a face with more than 255 vertices")
    case("face_255_corners", obj(*[f"v {math.cos(i * 0.02):.6f} {math.sin(i * 0.02):.6f} 0" for i in range(255)],
                                 "f " + " ".join(str(i + 1) for i in range(255)), mtllib=None), "loads")
    case("many_corners_one_line", obj(*TRI, "f " + " ".join(["1 2 3"] * 20000), mtllib=None), "error",
         "more than 255 vertices")
    case("line_out_of_range", obj(*TRI, "l 1 99", "f 1 2 3", mtllib=None), "any")
    case("point_out_of_range", obj(*TRI, "p -99 4", "f 1 2 3", mtllib=None), "any")
    case("lines_only", obj(*TRI, "l 1 2 3", mtllib=None), "loads", "only faces are rendered")

    # Numbers tinyobjloader would read as 0, or beyond float.
    for name, line, mentions in [
        ("v_nan", "v nan 0 0", "v value 'nan' is not a finite number"),
        ("v_inf", "v 0 inf 0", "v value 'inf' is not a finite number"),
        ("v_1e39", "v 1e39 0 0", "v #4 is not a finite float"),
        ("v_1e999", "v 0 0 1e999", "v value '1e999' is not a finite number"),
        ("v_0e999", "v 0e999 0 0", "v #4 is not a finite float"),  # 0 * 10^999 to from_chars, NaN to tinyobj
        ("v_exponent_overflow", "v 1e99999999999999 0 0", "is not a finite number"),
        ("vp_exponent_int_overflow", "vp 1e2147483648", "the number '1e2147483648' has an exponent out of range"),
        ("v_letters", "v 1 x 0", "v value 'x' is not a finite number"),
        ("v_hex", "v 0x10 0 0", "is not a finite number"),
        ("v_one_component", "v 1", ""),
        ("v_colours", "v 0 0 0 1 0.5 0", ""),
        ("v_colours_nan", "v 0 0 0 nan 0 0", "is not a finite number"),
        ("vn_nan", "vn nan 0 1", "vn value 'nan'"),
        ("vn_1e39", "vn 1e39 0 1", "vn #1 is not a finite float"),
        ("vt_nan", "vt 0.5 NaN", "vt value 'NaN'"),
        ("vt_1e39", "vt 1e39 0", "vt #1 is not a finite float"),
        ("vw_huge", "vw 1 2147483648 1e300 -99999999999", ""),
        ("vp_nan", "vp nan nan", ""),
    ]:
        expect = "error" if mentions else "any"
        case(name, obj(*TRI, line, "f 1 2 3", mtllib=None), expect, mentions)

    # Material libraries and textures outside the folder, missing, or broken.
    for name, mtllib, expect, mentions in [
        ("mtllib_parent", "../outside.mtl", "error", "mtllib '../outside.mtl' leads outside"),
        ("mtllib_symlink", "escape/outside.mtl", "error", "leads outside the scene folder"),
        ("mtllib_absolute", "/etc/passwd", "error", "absolute path"),
        ("mtllib_url", "http://example.com/a.mtl", "error", "is a URL"),
        ("mtllib_missing", "missing.mtl", "loads", "material library 'missing.mtl' not found"),
        ("mtllib_folder", "folder.bin", "error", "is not a regular file"),
        ("mtllib_binary", "buffer.bin", "any", ""),
        ("mtllib_many", " ".join(["missing.mtl"] * 50) + " base.mtl", "any", ""),
        ("mtllib_empty", "", "any", ""),
    ]:
        case(name, obj(*TRI, "usemtl plain", "f 1 2 3", mtllib=mtllib), expect, mentions)
    case("usemtl_unknown", obj(*TRI, "usemtl nothing", "f 1 2 3"), "any")
    # Names that are not UTF-8, or whose quote would cut a character in two, in messages.
    case("mtllib_bad_utf8", obj(*TRI, "f 1 2 3", mtllib=None) + b"mtllib \xff\xfe\x1b[31m.mtl\n", "loads",
         "material library '??\u003f[31m.mtl' not found")
    case("mtllib_long_utf8", obj(*TRI, "f 1 2 3", mtllib="\u00e9" * 100 + ".mtl"), "loads",
         "'" + "\u00e9" * 60 + "...'")
    case("usemtl_bad_utf8", obj(*TRI, "usemtl @@", "f 1 2 3").replace(b"@@", b"\xff\xfe"), "loads",
         "material [ '??' ] not found")
    case("object_bad_utf8", obj(*TRI, "o \u00e9", "f 1 2 3", mtllib=None).replace(b"\xc3\xa9", b"\xc3"), "loads")
    case("usemtl_before_mtllib", b"usemtl plain\n" + obj(*TRI, "f 1 2 3"), "any")

    def mtl_case(name: str, mtl: str, expect: str = "error", mentions: str = "", uses: str = "m") -> None:
        c.companion(f"obj_mtl_{name}.mtl", mtl.encode())
        c.add(f"obj_mtl_{name}.obj", obj(*TRI, f"usemtl {uses}", "f 1 2 3", mtllib=f"obj_mtl_{name}.mtl"),
              expect, mentions)
    for name, body, expect, mentions in [
        ("kd_negative", "Kd 0.5 -1 0.5", "error", "has a negative Kd, Ks or Ns"),
        ("kd_nan", "Kd nan 0 0", "any", ""),
        ("kd_1e400", "Kd 1e400 0 0", "error", "not a finite float"),
        ("kd_exponent_overflow", "Kd 1e99999999999999 0 0", "error", "has an exponent out of range"),
        ("ns_exponent_int_overflow", "Ns 5.E-2147483649", "error", "obj_mtl_ns_exponent_int_overflow.mtl: line 2: "
         "the number '5.E-2147483649' has an exponent out of range"),
        ("ns_1e400", "Ns 1e400", "error", "has a Kd, Ks or Ns"),
        ("ns_negative", "Ns -5", "error", "negative"),
        ("ni_zero_transparent", "d 0.5\nNi 0", "error", "with Ni 0, expected an index of refraction of at least 1"),
        ("ni_1e400", "d 0.5\nNi 1e400", "error", "d, Tr or Ni"),
        ("d_nan", "d nan", "any", ""),
        ("tr_huge", "Tr 1e400", "error", "d, Tr or Ni"),
        ("illum_huge", "illum 99999999999999", "any", ""),
        ("map_parent", "map_Kd ../outside.bin", "error", "map_Kd '../outside.bin' leads outside"),
        ("map_absolute", "map_Kd /etc/passwd", "error", "absolute path"),
        ("map_symlink", "map_Kd escape/outside.bin", "error", "leads outside the scene folder"),
        ("map_url", "map_Kd https://example.com/t.png", "error", "is a URL"),
        ("map_missing", "map_Kd missing.png", "loads", "not found: texture ignored"),
        ("map_not_image", "map_Kd buffer.bin", "loads", "is not a PNG, JPEG, BMP, TGA or WebP image"),
        ("map_folder", "map_Kd folder.bin", "error", "is not a regular file"),
        ("map_options_huge", "map_Kd -s 1e999 1e999 1e999 -o -1e999 0 0 -texres 99999999999 -bm nan image.png",
         "any", ""),
        ("map_options_only", "map_Kd -clamp on -blendu off", "any", ""),
        ("map_option_unfinished", "map_Kd -s", "any", ""),
        ("newmtl_empty", "newmtl\nKd 1 1 1", "any", ""),
        ("binary", "\x00\x01\x02\xff" * 64, "any", ""),
    ]:
        mtl_case(name, f"newmtl m\n{body}\n", expect, mentions)

    # Text that is not text, and lines that never end.
    case("binary", bytes(range(256)) * 8, "any")
    case("nul_bytes", obj(*TRI, "f 1 2 3", mtllib=None).replace(b"\n", b"\0\n"), "any")
    case("cr_only", obj(*TRI, "f 1 2 3", mtllib=None).replace(b"\n", b"\r"), "any")
    case("crlf", obj(*TRI, "f 1 2 3", mtllib=None).replace(b"\n", b"\r\n"), "loads")
    case("long_line", obj(*TRI, "f 1 2 3", "o " + "x" * 200000, mtllib=None), "any")
    case("long_number", obj("v " + "9" * 5000 + " 0 0", *TRI[1:], "f 1 2 3", mtllib=None), "error", "")
    case("many_tokens", obj("v " + " ".join(["0"] * 50000), *TRI, "f 2 3 4", mtllib=None), "any")
    case("empty", b"", "loads")
    case("only_comments", b"# nothing\n#\n", "loads")
    case("degenerate", obj("v 0 0 0", "v 0 0 0", "v 0 0 0", "f 1 2 3", mtllib=None), "loads", "degenerate")
