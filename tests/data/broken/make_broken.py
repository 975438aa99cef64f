#!/usr/bin/env python3
"""Writes the broken glTF files the bad-input tests feed to the loader and to `candela`.

Each file is a one-triangle scene with exactly one thing wrong (named by the file). Rerun with
/usr/bin/python3 tests/data/broken/make_broken.py after changing it; the outputs are committed.
"""
import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def triangle_bin():
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    indices = struct.pack("<3I", 0, 1, 2)
    return positions + indices


def base_gltf(bin_name, bin_len):
    return {
        "asset": {"version": "2.0", "generator": "candela make_broken.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "triangle"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}}],
        "buffers": [{"uri": bin_name, "byteLength": bin_len}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 12},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"},
        ],
    }


def write_png(name, rgb):
    """A 1x1 RGB PNG of colour rgb (bytes), written with zlib: signature, IHDR, IDAT, IEND."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(b"\x00" + rgb)) + chunk(b"IEND", b"")
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(png)


def write(name, gltf, bin_bytes=None, bin_name=None):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    if bin_bytes is not None:
        with open(os.path.join(HERE, bin_name), "wb") as f:
            f.write(bin_bytes)


def main():
    data = triangle_bin()

    # 1. The .bin file is shorter than the buffer's byteLength.
    write("truncated_buffer.gltf", base_gltf("truncated_buffer.bin", len(data)), data[:30], "truncated_buffer.bin")

    # 2. An index points past the vertices.
    bad = data[:36] + struct.pack("<3I", 0, 1, 4096)
    write("index_out_of_range.gltf", base_gltf("index_out_of_range.bin", len(bad)), bad, "index_out_of_range.bin")

    # 3. An accessor claims more elements than its buffer view holds.
    g = base_gltf("accessor_past_view.bin", len(data))
    g["accessors"][0]["count"] = 300
    write("accessor_past_view.gltf", g, data, "accessor_past_view.bin")

    # 4. A texture file that does not exist.
    g = base_gltf("missing_texture.bin", len(data))
    g["images"] = [{"uri": "does_not_exist.png"}]
    g["textures"] = [{"source": 0}]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    write("missing_texture.gltf", g, data, "missing_texture.bin")

    # 4b. A texture file that exists but is no image (the loader decodes images on several
    # threads; a failed one is decoded again alone for stb_image's reason), and a valid one.
    g = base_gltf("missing_texture.bin", len(data))
    g["images"] = [{"uri": "not_an_image.png"}, {"uri": "one_pixel.png"}]
    g["textures"] = [{"source": 0}, {"source": 1}]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    g["materials"][0]["emissiveTexture"] = {"index": 1}
    write("undecodable_texture.gltf", g)
    with open(os.path.join(HERE, "not_an_image.png"), "w") as f:
        f.write("this is text, not a PNG\n")
    write_png("one_pixel.png", bytes([255, 128, 0]))

    # 5. Not valid JSON (a missing comma).
    text = json.dumps(base_gltf("bad_json.bin", len(data)), indent=1)
    text = text.replace('"scene": 0,', '"scene": 0', 1)
    with open(os.path.join(HERE, "bad_json.gltf"), "w") as f:
        f.write(text + "\n")

    # More: a node referring to a mesh that does not exist, and a node hierarchy with a cycle.
    g = base_gltf("missing_texture.bin", len(data))
    g["nodes"][0]["mesh"] = 7
    write("bad_mesh_reference.gltf", g)
    g = base_gltf("missing_texture.bin", len(data))
    g["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [0]}]
    write("node_cycle.gltf", g)

    # KHR_texture_basisu required by a texture without a PNG/JPEG `source` to fall back to.
    write("basisu_required_no_fallback.gltf", {
        "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_texture_basisu"], "extensionsRequired": ["KHR_texture_basisu"],
        "images": [{"uri": "logo.ktx2", "mimeType": "image/ktx2"}],
        "textures": [{"extensions": {"KHR_texture_basisu": {"source": 0}}}]})
    # Box-Draco (tests/data/models, its Box.bin as a data URI) whose POSITION names a Draco
    # attribute id the compressed mesh does not have.
    models = os.path.join(HERE, "..", "models", "Box-Draco")
    with open(os.path.join(models, "Box.gltf")) as f:
        g = json.load(f)
    with open(os.path.join(models, "Box.bin"), "rb") as f:
        g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(f.read()).decode()
    g["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 7
    write("draco_unknown_attribute.gltf", g)


if __name__ == "__main__":
    main()
