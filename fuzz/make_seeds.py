#!/usr/bin/env python3
"""Writes the hand-made seeds of fuzz/corpus (docs/fuzzing.md): tiny valid files of every format the readers
take and a few broken ones (truncated, wrong sizes). Run from the repository root: python3 fuzz/make_seeds.py.
The sidecar and GDM asset seeds come from the targets' own fixtures (STRATA_FUZZ_SEED_OUT, scripts/fuzz.sh
--seed) and the JSON examples from examples/; this script only adds to fuzz/corpus."""
import base64
import json
import os
import shutil
import struct
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    d = os.path.join(ROOT, "fuzz_" + target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def png(width, height, color_type, bit_depth, channels, interlace=0):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    bpp = channels * bit_depth // 8
    raw = b""
    for y in range(height):
        raw += b"\x00" + bytes(((x * 37 + y * 11 + c * 5) & 0xFF) for x in range(width) for c in range(bpp))
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, interlace)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def tga(width, height, rle, channels):
    image_type = (10 if rle else 2) if channels >= 3 else (11 if rle else 3)
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, image_type, 0, 0, 0, 0, 0, width, height, channels * 8,
                         0x20 | (8 if channels == 4 else 0))
    pixels = b""
    for n in range(width * height):
        px = bytes(((n * 29 + c * 70) & 0xFF) for c in range(channels))
        pixels += (b"\x00" + px) if rle else px
    return header + pixels


def bmp(width, height, bits):
    row = ((width * bits // 8) + 3) & ~3
    pixels = b""
    for y in range(height):
        line = bytes(((x * 40 + y * 20 + c) & 0xFF) for x in range(width) for c in range(bits // 8))
        pixels += line + b"\x00" * (row - len(line))
    header = b"BM" + struct.pack("<IHHI", 54 + len(pixels), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, width, height, 1, bits, 0, len(pixels), 2835, 2835, 0, 0)
    return header + info + pixels


def main():
    pydata = "/root/.pyenv/versions/3.7.16/lib/python3.7/test/imghdrdata"  # CPython's imghdr test images (PSF)
    # Images.
    put("png", "gray8.png", png(4, 3, 0, 8, 1))
    put("png", "gray16.png", png(4, 3, 0, 16, 1))
    put("png", "rgb8.png", png(3, 2, 2, 8, 3))
    put("png", "rgb16.png", png(3, 2, 2, 16, 3))
    put("png", "rgba8_interlaced.png", png(5, 5, 6, 8, 4, interlace=1))
    put("png", "graya8.png", png(2, 2, 4, 8, 2))
    put("png", "truncated.png", png(4, 3, 2, 8, 3)[:40])
    put("png", "huge_header.png", png(1, 1, 0, 8, 1)[:16] + struct.pack(">II", 0x7FFFFFFF, 0x7FFFFFFF)
        + png(1, 1, 0, 8, 1)[24:])
    put("tga", "rgb.tga", tga(3, 2, False, 3))
    put("tga", "rgba_rle.tga", tga(4, 2, True, 4))
    put("tga", "gray.tga", tga(2, 2, False, 1))
    put("tga", "truncated.tga", tga(4, 4, False, 3)[:30])
    put("bmp", "rgb24.bmp", bmp(3, 2, 24))
    put("bmp", "rgba32.bmp", bmp(2, 2, 32))
    put("bmp", "truncated.bmp", bmp(4, 4, 24)[:60])
    for ext, target in (("jpg", "jpg"), ("exr", "exr"), ("bmp", "bmp"), ("png", "png")):
        src = os.path.join(pydata, "python." + ext)
        if os.path.exists(src):
            data = open(src, "rb").read()
            put(target, "python." + ext, data)
            put(target, "python_truncated." + ext, data[: len(data) // 2])
    # Meshes.
    quad_obj = ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                "f 1/1/1 2/2/1 3/3/1 4/4/1\n")
    put("obj", "quad.obj", quad_obj)
    put("obj", "triangle_no_uv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    put("obj", "negative_indices.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n")
    put("obj", "bad_index.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    put("off", "tetra.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
    put("off", "quad_comment.off", "OFF # a quad\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    put("off", "coff.off", "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n")
    put("off", "bad_count.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n")
    # glTF: one triangle with positions, normals, uvs and indices in one embedded buffer.
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    nrm = struct.pack("<9f", 0, 0, 1, 0, 0, 1, 0, 0, 1)
    uv = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    idx = struct.pack("<3H", 0, 1, 2) + b"\x00\x00"
    buf = pos + nrm + uv + idx

    def gltf_doc(uri):
        doc = {
            "asset": {"version": "2.0"},
            "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                        "indices": 3}]}],
            "buffers": [{"byteLength": len(buf)}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 72, "byteLength": 24},
                            {"buffer": 0, "byteOffset": 96, "byteLength": 6}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
                {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        }
        if uri:
            doc["buffers"][0]["uri"] = uri
        return doc

    embedded = gltf_doc("data:application/octet-stream;base64," + base64.b64encode(buf).decode())
    put("gltf", "triangle.gltf", json.dumps(embedded))
    bad = gltf_doc("data:application/octet-stream;base64," + base64.b64encode(buf).decode())
    bad["accessors"][3]["count"] = 300
    put("gltf", "accessor_past_buffer.gltf", json.dumps(bad))
    put("gltf", "truncated.gltf", json.dumps(embedded)[:120])
    js = json.dumps(gltf_doc(None)).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    glb = struct.pack("<I", len(js)) + b"JSON" + js + struct.pack("<I", len(buf)) + b"BIN\x00" + buf
    put("glb", "triangle.glb", b"glTF" + struct.pack("<II", 2, 12 + len(glb)) + glb)
    put("glb", "truncated.glb", (b"glTF" + struct.pack("<II", 2, 12 + len(glb)) + glb)[:50])
    # Solid OBJ: a closed, consistently oriented box inside the tile (H = 0.5).
    cube = "# box\n" + "".join("v %g %g %g\n" % (x, y, z) for z in (0.1, 0.4) for y in (0.2, 0.8) for x in (0.2, 0.8))
    for f in ((1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)):
        cube += "f %d %d %d %d\n" % f
    put("solid_obj", "box.obj", cube)
    put("solid_obj", "open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    put("solid_obj", "relative.obj", cube.replace("f 1 3 4 2", "f -8/1/1 -6 -5 -7"))
    put("solid_obj", "bad_line.obj", "v 0 0\nf 1 2\n")
    # JSON: the repository's examples, and broken ones.
    os.makedirs(os.path.join(ROOT, "fuzz_material"), exist_ok=True)
    os.makedirs(os.path.join(ROOT, "fuzz_scene"), exist_ok=True)
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for name in ("shaped_fabric.json", "three_layers.json", "fractional_tiling.json", "shaped_metal.json"):
        shutil.copy(os.path.join(repo, "examples", name), os.path.join(ROOT, "fuzz_material", name))
    put("material", "truncated.json", open(os.path.join(repo, "examples", "three_layers.json")).read()[:90])
    put("material", "wrong_types.json", '{"layers": [{"pattern": 3, "weight": "a"}], "ao": []}')
    scenes = os.path.join(repo, "examples", "scenes")
    for name in sorted(os.listdir(scenes)):
        shutil.copy(os.path.join(scenes, name), os.path.join(ROOT, "fuzz_scene", name))
    put("scene", "wrong_types.json", '{"mesh": 1, "camera": {"fov": "x"}, "material": null}')
    put("scene", "deep.json", "[" * 600 + "]" * 600)


if __name__ == "__main__":
    main()
