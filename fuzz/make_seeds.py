#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora.

    python3 fuzz/make_seeds.py            # fuzz/corpus/<target>/: small seeds, committed
    python3 fuzz/make_seeds.py --shared   # also fuzz/corpus-shared/<target>/ from ../shared/data
                                          # (never committed: the data stays outside the repo)

The committed seeds are the repository's own small scenes and meshes and hand-made inputs
(one per loader feature); the shared seeds add the glTF samples, the assignment's normal images
(cut down to small crops) and small models, for longer runs.
"""

import base64
import json
import os
import struct
import sys
import zlib

FUZZ = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(FUZZ)
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "data")
SMALL = 16 * 1024  # the largest seed file taken


def write(corpus, target, name, data):
    folder = os.path.join(FUZZ, corpus, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def small_files(folder, suffixes):
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if name.endswith(suffixes) and os.path.isfile(path) and os.path.getsize(path) <= SMALL:
            with open(path, "rb") as f:
                yield name, f.read()


def png(width, height, rows, colour_type=6, depth=8):
    """A PNG of `rows` (bytes per row, without filter bytes)."""
    raw = b"".join(b"\x00" + r for r in rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", width, height, depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def triangle_gltf(extra=None, uri=None):
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    uri = uri or "data:application/octet-stream;base64," + base64.b64encode(positions).decode()
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"uri": uri, "byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    doc.update(extra or {})
    return json.dumps(doc)


def glb(json_text, binary):
    j = json_text.encode()
    j += b" " * (-len(j) % 4)
    binary += b"\x00" * (-len(binary) % 4)
    body = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(binary), b"BIN\x00") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def committed():
    c = "corpus"
    for name, data in small_files(os.path.join(ROOT, "meshes"), (".obj",)):
        mtl = b""
        if b"mtllib" in data:
            mtl_path = os.path.join(ROOT, "meshes", "cornell-box.mtl")
            mtl = open(mtl_path, "rb").read()
        write(c, "obj", name, data + b"\n#--mtl\n" + mtl)
    write(c, "obj", "polygon.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 1 0\nf 1 2 3 4 5\n")
    write(c, "obj", "textured.obj",
          "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\n"
          "\n#--mtl\nnewmtl a\nKd 0.5 0.5 0.5\nKs 0.5 0.5 0.5\nNs 30\nPr 0.4\nPm 0.1\nnorm -bm 1 n.png\n")
    write(c, "obj", "degenerate.obj", "v 0 0 0\nv 1 0 0\nf 1 2\nf 1\nf 1 1 1\nf 1 2 2\n")
    for folder in ("scenes", os.path.join("scenes", "validation")):
        for name, data in small_files(os.path.join(ROOT, folder), (".toml",)):
            text = data.decode()
            # Point the meshes at the ones the target writes beside the scene.
            for mesh in ("torus", "plane", "icosphere", "uv-sphere", "uv-sphere-coarse", "cornell-box",
                         "icosphere-no-normals"):
                text = text.replace(f'"../meshes/{mesh}.obj"', '"quad.obj"').replace(f'"../../meshes/{mesh}.obj"', '"tri.obj"')
            write(c, "scene_file", name, text)
    write(c, "normal_map_scene", "tp.toml",
          '[normal_map]\nimage = "n.png"\npreset = "tp"\nbrdf = "cook-torrance"\n')
    write(c, "normal_map_scene", "physical.toml",
          '[normal_map]\nimage = "n.png"\nmaterial = "m"\n\n[material.m]\nmodel = "blinn-phong"\nshininess = 40.0\n\n'
          '[[light]]\ntype = "point"\nposition = [0.0, 1.0, 1.0]\nintensity = 2.0\n')
    rgba = [bytes([128, 128, 255, 255, 200, 128, 200, 255, 0, 0, 0, 0]), bytes([90, 170, 230, 255] * 3)]
    write(c, "normal_image", "rgba8.png", png(3, 2, rgba))
    write(c, "normal_image", "rgb8.png", png(2, 2, [bytes([128, 128, 255] * 2)] * 2, colour_type=2))
    write(c, "normal_image", "rgb16.png", png(1, 1, [struct.pack(">3H", 32768, 40000, 65535)], colour_type=2, depth=16))
    write(c, "gltf", "triangle.gltf", triangle_gltf())
    write(c, "gltf", "camera.gltf", triangle_gltf({
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.5}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.2, 0.2, 3]}], "scenes": [{"nodes": [0, 1]}]}))
    write(c, "gltf", "external.gltf", triangle_gltf(uri="b.bin") + "\n#--bin\n" +
          struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0).decode("latin-1"))
    write(c, "gltf", "material.gltf", triangle_gltf({
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1], "metallicFactor": 0.3,
                                                "roughnessFactor": 0.4}, "doubleSided": True}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 20}]}},
        "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 1, 2]}],
        "scenes": [{"nodes": [0, 1]}]}))
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    doc = json.loads(triangle_gltf())
    del doc["buffers"][0]["uri"]
    write(c, "gltf", "triangle.glb", glb(json.dumps(doc), positions))
    # EXR seeds: pointshade's own output (a frame and a crop), written by the test binary's
    # library through `pointshade render` at the time the corpus was made.
    exr_dir = os.path.join(FUZZ, c, "exr")
    os.makedirs(exr_dir, exist_ok=True)
    binary = os.path.join(ROOT, "target", "release", "pointshade")
    if os.path.exists(binary):
        scene = os.path.join(ROOT, "scenes", "lambert.toml")
        os.system(f"'{binary}' render '{scene}' -o '{exr_dir}/frame.exr' --width 6 --height 4 --quiet")
        os.system(f"'{binary}' render '{scene}' -o '{exr_dir}/crop.exr' --width 6 --height 4 --crop 1,1,4,3 --quiet")
    else:
        print("target/release/pointshade missing: no EXR seeds (cargo build --release first)")


def shared():
    if not os.path.isdir(SHARED):
        sys.exit(f"{SHARED} missing")
    c = "corpus-shared"
    for root, _, files in os.walk(os.path.join(SHARED, "gltf")):
        for name in files:
            path = os.path.join(root, name)
            if name.endswith((".gltf", ".glb")) and os.path.getsize(path) <= 256 * 1024:
                write(c, "gltf", name, open(path, "rb").read())
    for name, data in small_files(os.path.join(SHARED, "meshes"), (".obj",)):
        write(c, "obj", name, data)
    try:
        from PIL import Image  # optional: crops of the assignment's images
    except ImportError:
        print("Pillow missing: no normal-image crops from ../shared/data/normalmaps")
        return
    import io
    for name in sorted(os.listdir(os.path.join(SHARED, "normalmaps"))):
        image = Image.open(os.path.join(SHARED, "normalmaps", name))
        w, h = image.size
        for k, (x, y) in enumerate([(w // 2, h // 2), (w // 3, h // 4), (0, 0)]):
            out = io.BytesIO()
            image.crop((x, y, x + 24, y + 24)).save(out, format="PNG")
            write(c, "normal_image", f"{name[:-4]}-{k}.png", out.getvalue())


if __name__ == "__main__":
    committed()
    if "--shared" in sys.argv:
        shared()
