#!/usr/bin/python3
"""Writes the small animated, skinned and morphed glTF files of tests/data/animation,
each with its buffer embedded as a base64 data: URI. Written for Candela's tests (no third-party
data). The valid files are also fuzz seeds (tests/fuzz/seeds). Run from this folder; the .gltf
files are committed, this script says how they were made.

Valid:
  two_bone_bar.gltf     a bar (y = 0..2) skinned to two joints (y = 0 and 1) with two influence
                        sets (JOINTS_0 ubyte + WEIGHTS_0 float, JOINTS_1 ushort + WEIGHTS_1
                        normalised ushort); animations "bend" (rotation LINEAR), "wave"
                        (translation CUBICSPLINE) and "blink" (scale STEP)
  shared_mesh.gltf      the same bar drawn by the skinned node and by a second, unskinned node
  weights_unnormalised.gltf  the bar with weights summing to 0.8 and one all-zero vertex
  morph_quad.gltf       a quad with two morph targets (POSITION + NORMAL; a sparse POSITION),
                        mesh weights [0.25, 0], a second node with its own weights [0, 1], and
                        animation "pulse" on the first node's weights
Rejected (reject_*.gltf), one problem each: see REJECTS below.
Fuzz seeds: tests/fuzz/seeds/two_bone_bar (the shared-mesh bar) and morph_quad, .gltf and .glb;
a regression: tests/fuzz/regressions/morph_normal_cancelled.gltf.
"""
import base64
import json
import math
import struct


class Gltf:
    def __init__(self):
        self.bin = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "tests/data/animation/make_animation_data.py"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
                    "bufferViews": [], "accessors": []}

    def view(self, data):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, fmt, component_type, type_, rows, normalized=False, minmax=False):
        """rows: list of tuples (or numbers for SCALAR)."""
        rows = [r if isinstance(r, (tuple, list)) else (r,) for r in rows]
        data = b"".join(struct.pack("<" + fmt * len(r), *r) for r in rows)
        # 1- and 2-byte vectors: each element padded to 4 bytes is not needed for VEC4.
        a = {"bufferView": self.view(data), "componentType": component_type, "count": len(rows), "type": type_}
        if normalized:
            a["normalized"] = True
        if minmax:  # over the finite values (JSON has no NaN)
            a["min"] = [min(r[i] for r in rows if math.isfinite(r[i])) for i in range(len(rows[0]))]
            a["max"] = [max(r[i] for r in rows if math.isfinite(r[i])) for i in range(len(rows[0]))]
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def floats(self, type_, rows, minmax=False):
        return self.accessor("f", 5126, type_, rows, minmax=minmax)

    def node(self, node, root=True):
        self.doc["nodes"].append(node)
        i = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(i)
        return i

    def write(self, name):
        self.doc["buffers"] = [{"byteLength": len(self.bin),
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()}]
        with open(name, "w") as f:
            json.dump(self.doc, f, indent=1)
            f.write("\n")

    def write_glb(self, name):
        """The same as binary glTF (JSON chunk + BIN chunk), so that a fuzzer mutates the data too."""
        doc = dict(self.doc)
        doc["buffers"] = [{"byteLength": len(self.bin)}]
        j = json.dumps(doc, separators=(",", ":")).encode()
        j += b" " * ((4 - len(j) % 4) % 4)
        binary = bytes(self.bin) + b"\0" * ((4 - len(self.bin) % 4) % 4)
        body = struct.pack("<II", len(j), 0x4E4F534A) + j + struct.pack("<II", len(binary), 0x004E4942) + binary
        with open(name, "wb") as f:
            f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def quat_z(deg):
    a = math.radians(deg) / 2
    return (0.0, 0.0, math.sin(a), math.cos(a))


def bar(shared=False, weights="normal", joints_ibm=2, joint_nodes=None, joint_value=None, times=(0.0, 1.0),
        rotation_values=None, cubic_keys=2, extra_output=0):
    """The two-bone bar; the keyword arguments break it in one way each for the reject_* files."""
    g = Gltf()
    pos = [(-0.25, 0, 0), (0.25, 0, 0), (-0.25, 1, 0), (0.25, 1, 0), (-0.25, 2, 0), (0.25, 2, 0)]
    nrm = [(0, 0, 1)] * 6
    idx = [0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4]
    # Influences: row y=0 on joint 0, y=1 half and half (set 0 joint 0, set 1 joint 1), y=2 on joint 1.
    j0 = [(0, 0, 0, 0)] * 6
    j1 = [(1, 0, 0, 0)] * 6
    if weights == "normal":
        w0 = [(1, 0, 0, 0)] * 2 + [(0.5, 0, 0, 0)] * 2 + [(0, 0, 0, 0)] * 2
        w1 = [(0, 0, 0, 0)] * 2 + [(32768, 0, 0, 0)] * 2 + [(65535, 0, 0, 0)] * 2
    else:  # sums of 0.8, and vertex 5 with no weight at all
        w0 = [(0.8, 0, 0, 0)] * 2 + [(0.4, 0, 0, 0)] * 2 + [(0, 0, 0, 0)] * 2
        w1 = [(0, 0, 0, 0)] * 2 + [(26214, 0, 0, 0)] * 2 + [(52428, 0, 0, 0), (0, 0, 0, 0)]
    if joint_value is not None:
        j1 = j1[:5] + [(joint_value, 0, 0, 0)]
    attrs = {"POSITION": g.floats("VEC3", pos, minmax=True), "NORMAL": g.floats("VEC3", nrm),
             "JOINTS_0": g.accessor("B", 5121, "VEC4", j0), "WEIGHTS_0": g.floats("VEC4", w0),
             "JOINTS_1": g.accessor("H", 5123, "VEC4", j1), "WEIGHTS_1": g.accessor("H", 5123, "VEC4", w1, normalized=True)}
    ind = g.accessor("H", 5123, "SCALAR", idx)
    g.doc["meshes"].append({"name": "bar", "primitives": [{"attributes": attrs, "indices": ind}]})
    g.node({"name": "bar", "mesh": 0, "skin": 0})
    g.node({"name": "root joint", "children": [2]})
    g.node({"name": "tip joint", "translation": [0, 1, 0]}, root=False)
    if shared:
        g.node({"name": "rigid copy", "mesh": 0, "translation": [3, 0, 0]})
    ibm = [(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1), (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1)]
    g.doc["skins"] = [{"name": "bar skin", "joints": joint_nodes or [1, 2], "skeleton": 1,
                       "inverseBindMatrices": g.floats("MAT4", ibm[:joints_ibm])}]
    t = g.floats("SCALAR", list(times), minmax=True)
    rot = rotation_values or [quat_z(0), quat_z(90)] + [quat_z(90)] * extra_output
    cubic_t = g.floats("SCALAR", [0.0, 2.0][:cubic_keys] if cubic_keys <= 2 else [0.0, 1.0, 2.0], minmax=True)
    # CUBICSPLINE: (in-tangent, value, out-tangent) per keyframe.
    wave = [(0, 0, 0), (0, 0, 0), (1, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 0)]
    g.doc["animations"] = [
        {"name": "bend", "samplers": [{"input": t, "output": g.floats("VEC4", rot)}],
         "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}]},
        {"name": "wave", "samplers": [{"input": cubic_t, "output": g.floats("VEC3", wave), "interpolation": "CUBICSPLINE"}],
         "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}]},
        {"name": "blink", "samplers": [{"input": g.floats("SCALAR", [0.5, 1.5], minmax=True),
                                        "output": g.floats("VEC3", [(1, 1, 1), (1, 0.5, 1)]), "interpolation": "STEP"}],
         "channels": [{"sampler": 0, "target": {"node": 2, "path": "scale"}}]},
    ]
    return g


def morph_quad(targets_second_primitive=None, mesh_weights=(0.25, 0.0), node_weights=(0.0, 1.0), short_delta=False,
               pulse_values=None, normal_delta=(0, -0.5, 0)):
    g = Gltf()
    pos = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    nrm = [(0, 0, 1)] * 4
    p = g.floats("VEC3", pos, minmax=True)
    n = g.floats("VEC3", nrm)
    ind = g.accessor("H", 5123, "SCALAR", [0, 1, 2, 0, 2, 3])
    lift = [(0, 0, 0), (0, 0, 0), (0, 0, 1), (0, 0, 1)][: 3 if short_delta else 4]
    t0 = {"POSITION": g.floats("VEC3", lift, minmax=True),
          "NORMAL": g.floats("VEC3", [(0, 0, 0), (0, 0, 0), normal_delta, normal_delta])}
    # Target 1 moves every vertex by +1 in x, as a sparse accessor over zeros.
    sparse_i = g.view(struct.pack("<4H", 0, 1, 2, 3))
    sparse_v = g.view(struct.pack("<12f", *([1, 0, 0] * 4)))
    g.doc["accessors"].append({"componentType": 5126, "count": 4, "type": "VEC3", "min": [1, 0, 0], "max": [1, 0, 0],
                               "sparse": {"count": 4, "indices": {"bufferView": sparse_i, "componentType": 5123},
                                          "values": {"bufferView": sparse_v}}})
    t1 = {"POSITION": len(g.doc["accessors"]) - 1}
    prims = [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": ind, "targets": [t0, t1]}]
    if targets_second_primitive is not None:
        prims.append({"attributes": {"POSITION": p, "NORMAL": n}, "indices": ind, "targets": [t0, t1][:targets_second_primitive]})
    mesh = {"name": "quad", "primitives": prims}
    if mesh_weights is not None:
        mesh["weights"] = list(mesh_weights)
    g.doc["meshes"].append(mesh)
    g.node({"name": "animated quad", "mesh": 0})
    second = {"name": "own weights", "mesh": 0, "translation": [3, 0, 0]}
    if node_weights is not None:
        second["weights"] = list(node_weights)
    g.node(second)
    times = g.floats("SCALAR", [0.0, 1.0, 2.0], minmax=True)
    values = pulse_values or [0, 0, 1, 0.5, 0, 0]
    g.doc["animations"] = [{"name": "pulse", "samplers": [{"input": times, "output": g.floats("SCALAR", values)}],
                            "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}]}]
    return g


bar().write("two_bone_bar.gltf")
bar(shared=True).write("shared_mesh.gltf")
bar(weights="unnormalised").write("weights_unnormalised.gltf")
morph_quad().write("morph_quad.gltf")
# Fuzz seeds (tests/fuzz/seeds): the skinned and the morphed file, as .gltf and .glb.
for name, make in [("two_bone_bar", lambda: bar(shared=True)), ("morph_quad", morph_quad)]:
    make().write(f"../../fuzz/seeds/{name}.gltf")
    make().write_glb(f"../../fuzz/seeds/{name}.glb")

# A fuzz regression (valid file): at weight 1 target 0's NORMAL delta cancels the normal of
# vertices 2 and 3; posing must keep unit normals (it falls back to the rest normal).
g = morph_quad(mesh_weights=(1.0, 0.0), normal_delta=(0, 0, -1))
g.doc["asset"]["generator"] += ": a morph target cancelling normals (fuzz regression)"
g.write("../../fuzz/regressions/morph_normal_cancelled.gltf")

# One problem each; the test checks the message names the file and this JSON path.
REJECTS = {
    "reject_times_not_increasing": (lambda: bar(times=(0.0, 0.0)), "animations[0].samplers[0].input"),
    "reject_nan_time": (lambda: bar(times=(0.0, float("nan"))), "animations[0].samplers[0].input"),
    "reject_inf_output": (lambda: bar(rotation_values=[quat_z(0), (0, 0, float("inf"), 1)]), "animations[0].samplers[0].output"),
    "reject_output_count": (lambda: bar(extra_output=1), "animations[0].channels[0].sampler"),
    "reject_cubic_output_count": (lambda: bar(cubic_keys=3), "animations[1].channels[0].sampler"),
    "reject_weights_output_count": (lambda: morph_quad(pulse_values=[0, 0, 1]), "animations[0].channels[0].sampler"),
    "reject_joint_out_of_range": (lambda: bar(joint_value=2), "meshes[0].primitives[0].attributes.JOINTS_1"),
    "reject_skin_joint_not_a_node": (lambda: bar(joint_nodes=[1, 7]), "skins[0].joints"),
    "reject_too_few_inverse_bind_matrices": (lambda: bar(joints_ibm=1), "skins[0].inverseBindMatrices"),
    "reject_morph_target_counts": (lambda: morph_quad(targets_second_primitive=1), "meshes[0].primitives[1].targets"),
    "reject_mesh_weights_count": (lambda: morph_quad(mesh_weights=(0.25, 0.0, 1.0)), "meshes[0].weights"),
    "reject_node_weights_count": (lambda: morph_quad(node_weights=(1.0,)), "nodes[1].weights"),
    "reject_morph_delta_count": (lambda: morph_quad(short_delta=True), "meshes[0].primitives[0].targets[0].POSITION"),
}
for name, (make, _) in REJECTS.items():
    make().write(name + ".gltf")
with open("rejects.json", "w") as f:
    json.dump({name: path for name, (_, path) in REJECTS.items()}, f, indent=1)
    f.write("\n")
