#!/usr/bin/env python3
"""Writes box_on_floor.gltf: a unit box on a floor (14 triangles, buffer embedded as base64), the
consumer project's scene. No camera or light: Candela frames the bounds and adds its default rig.

    python3 make_scene.py            (in tests/consumer/scenes)
"""
import base64
import json
import struct


def quad_faces():
    # Each face of the unit box: normal, and two axes spanning it (counter-clockwise seen from outside).
    return [((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
            ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
            ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0))]


def box():
    positions, normals, indices = [], [], []
    for n, u, v in quad_faces():
        base = len(positions)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            positions.append(tuple(0.5 * (n[i] + su * u[i] + sv * v[i]) for i in range(3)))
            normals.append(n)
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, indices


def floor():
    y = -0.5
    positions = [(-2, y, 2), (2, y, 2), (2, y, -2), (-2, y, -2)]
    return positions, [(0, 1, 0)] * 4, [0, 1, 2, 0, 2, 3]


def main():
    blob = bytearray()
    views, accessors, meshes = [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for name, (pos, nrm, idx), material in (("box", box(), 0), ("floor", floor(), 1)):
        p = add_view(b"".join(struct.pack("<3f", *x) for x in pos), 34962)
        n = add_view(b"".join(struct.pack("<3f", *x) for x in nrm), 34962)
        i = add_view(struct.pack("<%dH" % len(idx), *idx), 34963)
        lo = [min(x[k] for x in pos) for k in range(3)]
        hi = [max(x[k] for x in pos) for k in range(3)]
        accessors += [{"bufferView": p, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": n, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
                      {"bufferView": i, "componentType": 5123, "count": len(idx), "type": "SCALAR"}]
        a = len(accessors) - 3
        meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": a, "NORMAL": a + 1}, "indices": a + 2,
                                                     "material": material}]})
    gltf = {
        "asset": {"version": "2.0", "generator": "Candela tests/consumer/scenes/make_scene.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "box", "mesh": 0, "rotation": [0, 0.2588190, 0, 0.9659258]}, {"name": "floor", "mesh": 1}],
        "meshes": meshes,
        "materials": [
            {"name": "box_red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0], "metallicFactor": 0.0,
                                                         "roughnessFactor": 0.5}},
            {"name": "floor_grey", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0,
                                                            "roughnessFactor": 0.9}},
        ],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    # One line per top-level key and per material: the consumer project alters the box's colour by a
    # plain text replacement of its baseColorFactor.
    lines = []
    for key, value in gltf.items():
        if key == "materials":
            lines.append('"materials": [\n  ' + ",\n  ".join(json.dumps(m) for m in value) + "\n]")
        else:
            lines.append(json.dumps(key) + ": " + json.dumps(value))
    with open("box_on_floor.gltf", "w") as f:
        f.write("{\n" + ",\n".join(lines) + "\n}\n")


if __name__ == "__main__":
    main()
