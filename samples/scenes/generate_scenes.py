#!/usr/bin/python3
"""Generate Candela's sample glTF 2.0 scenes.

This script writes, next to itself, six small test scenes (one .gltf JSON file and one .bin
buffer per scene, plus fence.png for the transparency scene):

  cornell_box.gltf    classic Cornell box lit by an emissive ceiling quad (area light)
  cornell_point.gltf  the same box lit by a KHR_lights_punctual point light instead
  spheres.gltf        5x5 metallic x roughness sphere grid over a ground plane, sun + sky
  shadow_test.gltf    boxes, a thin pole and a floating slab under a spot light and a sun
  transparency.gltf   alpha-BLEND panes (overlapping and interpenetrating) + alpha-MASK fence
  reflections.gltf    small room with a mirror sphere, a glass sphere and a glossy floor

Conventions (see docs/design.md, "Scene conventions"): right-handed, +Y up, meters, linear RGB; light
intensities are radiometric (point/spot W/sr, directional W/m^2); constant environment radiance
goes in scenes[0].extras.environment_radiance; the spheres of reflections.gltf carry extras.reflection_probe; sphere nodes carry extras.sphere.radius (world
radius, the node has no scale) so a ray tracer can intersect the exact sphere.

Every mesh primitive is an indexed triangle list (UNSIGNED_INT indices) with POSITION (with
min/max) and NORMAL, plus TEXCOORD_0 where a texture is used. Faces are counter-clockwise seen
from the side their normal points to. After writing, the script re-reads and checks every file.

The output is deterministic (byte-identical on every run). Only the Python standard library is
used. To regenerate, from the repository root:

    /usr/bin/python3 samples/scenes/generate_scenes.py
"""

import json
import math
import os
import struct
import sys
import zlib

OUT_DIR = os.path.dirname(os.path.abspath(__file__))

FLOAT = 5126
UNSIGNED_INT = 5125
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963
NEAREST = 9728
REPEAT = 10497

SPHERE_SEGMENTS = 48
SPHERE_RINGS = 24


# ----------------------------------------------------------------------------------------------
# Small math helpers
# ----------------------------------------------------------------------------------------------

def r6(x):
    """Round a float to 6 significant digits; snap tiny values (and -0.0) to 0.0."""
    x = float(x)
    if abs(x) < 1e-9:
        return 0.0
    return float("%.6g" % x)


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def quat_from_basis(x, y, z):
    """Quaternion [x,y,z,w] of the rotation whose matrix columns are the axes x, y, z."""
    m00, m01, m02 = x[0], y[0], z[0]
    m10, m11, m12 = x[1], y[1], z[1]
    m20, m21, m22 = x[2], y[2], z[2]
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    if q[3] < 0.0:
        q = tuple(-c for c in q)
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def quat_look_along(forward):
    """Rotation that maps the local -Z axis onto `forward` (local +Y stays as up as possible)."""
    f = normalize(forward)
    up = (0.0, 1.0, 0.0) if abs(f[1]) < 0.999 else (0.0, 0.0, -1.0)
    z = mul(f, -1.0)
    x = normalize(cross(up, z))
    y = cross(z, x)
    return quat_from_basis(x, y, z)


def quat_look_at(eye, target):
    return quat_look_along(sub(target, eye))


def quat_y(degrees):
    a = math.radians(degrees) * 0.5
    return [0.0, math.sin(a), 0.0, math.cos(a)]


# ----------------------------------------------------------------------------------------------
# Geometry: each function returns a dict with positions, normals, optional uvs, indices
# ----------------------------------------------------------------------------------------------

def quad_geometry(center, normal, u_dir, half_u, half_v, uv_repeat=None):
    """A rectangle centred at `center` facing `normal` (CCW seen from that side).

    u_dir is the in-plane direction of the first edge; the second edge is normal x u_dir.
    uv_repeat=(ru, rv) adds TEXCOORD_0 spanning [0,ru] x [0,rv] (v grows downwards).
    """
    n = normalize(normal)
    u = normalize(u_dir)
    v = cross(n, u)
    du, dv = mul(u, half_u), mul(v, half_v)
    corners = [sub(sub(center, du), dv), sub(add(center, du), dv),
               add(add(center, du), dv), add(sub(center, du), dv)]
    geom = {"positions": corners, "normals": [n] * 4, "indices": [0, 1, 2, 0, 2, 3]}
    if uv_repeat is not None:
        ru, rv = uv_repeat
        geom["uvs"] = [(0.0, rv), (ru, rv), (ru, 0.0), (0.0, 0.0)]
    return geom


def merge_geometry(parts):
    out = {"positions": [], "normals": [], "indices": []}
    has_uv = all("uvs" in p for p in parts)
    if has_uv:
        out["uvs"] = []
    for p in parts:
        base = len(out["positions"])
        out["positions"] += p["positions"]
        out["normals"] += p["normals"]
        if has_uv:
            out["uvs"] += p["uvs"]
        out["indices"] += [base + i for i in p["indices"]]
    return out


def box_geometry(size):
    """Axis-aligned box centred at the origin with flat normals (24 vertices, 12 triangles)."""
    h = (size[0] * 0.5, size[1] * 0.5, size[2] * 0.5)
    faces = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            n = tuple(n)
            u = (1.0, 0.0, 0.0) if axis == 1 else cross((0.0, 1.0, 0.0), n)
            v = cross(n, u)
            half_u = dot((abs(u[0]), abs(u[1]), abs(u[2])), h)
            half_v = dot((abs(v[0]), abs(v[1]), abs(v[2])), h)
            faces.append(quad_geometry(mul(n, h[axis]), n, u, half_u, half_v))
    return merge_geometry(faces)


def sphere_geometry(radius, segments=SPHERE_SEGMENTS, rings=SPHERE_RINGS):
    """UV sphere centred at the origin, built at `radius`, with smooth normals."""
    positions, normals = [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        st, ct = math.sin(theta), math.cos(theta)
        for j in range(segments + 1):
            phi = 2.0 * math.pi * (j % segments) / segments
            n = (st * math.cos(phi), ct, -st * math.sin(phi))
            if i == 0 or i == rings:
                n = (0.0, ct, 0.0)
            normals.append(n)
            positions.append(mul(n, radius))
    indices = []
    row = segments + 1
    for i in range(rings):
        for j in range(segments):
            a = i * row + j
            b = a + row
            if i != 0:
                indices += [a, b, a + 1]
            if i != rings - 1:
                indices += [a + 1, b, b + 1]
    return {"positions": positions, "normals": normals, "indices": indices}


# ----------------------------------------------------------------------------------------------
# PNG writer (RGBA8, no interlace)
# ----------------------------------------------------------------------------------------------

def png_bytes(width, height, rgba_rows):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes(row) for row in rgba_rows)  # filter type 0 on every row
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def fence_png():
    """64x64 grid: opaque off-white bars 6 px wide on a 16 px period, fully transparent gaps."""
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            bar = (x % 16) < 6 or (y % 16) < 6
            row += [235, 232, 222, 255] if bar else [235, 232, 222, 0]
        rows.append(row)
    return png_bytes(64, 64, rows)


# ----------------------------------------------------------------------------------------------
# glTF document builder
# ----------------------------------------------------------------------------------------------

class GltfBuilder:
    def __init__(self, name):
        self.name = name
        self.bin = bytearray()
        self.extensions_used = []
        self.nodes, self.cameras, self.meshes, self.materials = [], [], [], []
        self.textures, self.images, self.samplers = [], [], []
        self.accessors, self.buffer_views, self.lights = [], [], []
        self.scene_extras = {}
        self._geometry_cache = {}
        self._material_by_name = {}

    def use_extension(self, ext):
        if ext not in self.extensions_used:
            self.extensions_used.append(ext)

    # -- binary data --------------------------------------------------------------------------
    def _add_view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.bin),
                                  "byteLength": len(data), "target": target})
        self.bin += data
        return len(self.buffer_views) - 1

    def _add_float_accessor(self, values, kind, with_bounds):
        width = len(values[0])
        flat = [r6(c) for v in values for c in v]
        view = self._add_view(struct.pack("<%df" % len(flat), *flat), ARRAY_BUFFER)
        acc = {"bufferView": view, "componentType": FLOAT, "count": len(values), "type": kind}
        if with_bounds:
            acc["min"] = [min(flat[k::width]) for k in range(width)]
            acc["max"] = [max(flat[k::width]) for k in range(width)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def add_geometry(self, geom, key=None):
        """Upload a geometry once (cached by key); returns (attributes, indices accessor)."""
        if key is not None and key in self._geometry_cache:
            return self._geometry_cache[key]
        attributes = {"POSITION": self._add_float_accessor(geom["positions"], "VEC3", True),
                      "NORMAL": self._add_float_accessor(geom["normals"], "VEC3", False)}
        if "uvs" in geom:
            attributes["TEXCOORD_0"] = self._add_float_accessor(geom["uvs"], "VEC2", False)
        idx = geom["indices"]
        view = self._add_view(struct.pack("<%dI" % len(idx), *idx), ELEMENT_ARRAY_BUFFER)
        self.accessors.append({"bufferView": view, "componentType": UNSIGNED_INT,
                               "count": len(idx), "type": "SCALAR"})
        result = (attributes, len(self.accessors) - 1)
        if key is not None:
            self._geometry_cache[key] = result
        return result

    # -- scene objects ------------------------------------------------------------------------
    def material(self, name, base_color, metallic=0.0, roughness=1.0, alpha=1.0, **extra):
        """Create (or reuse, by name) a pbrMetallicRoughness material; returns its index."""
        if name in self._material_by_name:
            return self._material_by_name[name]
        pbr = {"baseColorFactor": list(base_color) + [alpha],
               "metallicFactor": metallic, "roughnessFactor": roughness}
        if "base_color_texture" in extra:
            pbr["baseColorTexture"] = {"index": extra.pop("base_color_texture")}
        mat = {"name": name, "pbrMetallicRoughness": pbr}
        if "emissive" in extra:
            mat["emissiveFactor"] = list(extra.pop("emissive"))
        for key in ("alphaMode", "alphaCutoff", "doubleSided"):
            if key in extra:
                mat[key] = extra.pop(key)
        exts = extra.pop("extensions", None)
        if exts:
            mat["extensions"] = exts
            for ext in exts:
                self.use_extension(ext)
        if extra:
            raise ValueError("unknown material options: %s" % sorted(extra))
        self.materials.append(mat)
        self._material_by_name[name] = len(self.materials) - 1
        return len(self.materials) - 1

    def mesh(self, name, geom, material, key=None):
        attributes, indices = self.add_geometry(geom, key)
        self.meshes.append({"name": name, "primitives": [{
            "attributes": dict(attributes), "indices": indices, "material": material,
            "mode": 4}]})
        return len(self.meshes) - 1

    def node(self, name, translation=None, rotation=None, **fields):
        node = {"name": name}
        if rotation is not None and [r6(c) for c in rotation] != [0.0, 0.0, 0.0, 1.0]:
            node["rotation"] = list(rotation)
        if translation is not None and any(r6(c) != 0.0 for c in translation):
            node["translation"] = list(translation)
        node.update(fields)
        self.nodes.append(node)
        return len(self.nodes) - 1

    def mesh_node(self, name, geom, material, translation=None, rotation=None, key=None,
                  extras=None):
        mesh = self.mesh(name, geom, material, key)
        fields = {"mesh": mesh}
        if extras:
            fields["extras"] = extras
        return self.node(name, translation, rotation, **fields)

    def sphere_node(self, name, center, radius, material, extras=None):
        return self.mesh_node(name, sphere_geometry(radius), material, translation=center,
                              key=("sphere", radius),
                              extras={"sphere": {"radius": radius}, **(extras or {})})

    def box_node(self, name, size, material, center, yaw_degrees=0.0):
        return self.mesh_node(name, box_geometry(size), material, translation=center,
                              rotation=quat_y(yaw_degrees), key=("box",) + tuple(size))

    def camera(self, name, eye, target, yfov=0.75):
        self.cameras.append({"name": name, "type": "perspective", "perspective": {
            "aspectRatio": 1.0, "yfov": yfov, "znear": 0.05}})
        return self.node(name, eye, quat_look_at(eye, target), camera=len(self.cameras) - 1)

    def light(self, name, kind, intensity, position, direction=None, color=(1.0, 1.0, 1.0),
              inner_cone=None, outer_cone=None):
        self.use_extension("KHR_lights_punctual")
        light = {"name": name, "type": kind, "color": list(color), "intensity": intensity}
        if kind == "spot":
            light["spot"] = {"innerConeAngle": inner_cone, "outerConeAngle": outer_cone}
        self.lights.append(light)
        rotation = quat_look_along(direction) if direction is not None else None
        return self.node(name, position, rotation,
                         extensions={"KHR_lights_punctual": {"light": len(self.lights) - 1}})

    def texture_png(self, name, uri, png, sampler):
        with open(os.path.join(OUT_DIR, uri), "wb") as f:
            f.write(png)
        self.images.append({"name": name, "uri": uri, "mimeType": "image/png"})
        self.samplers.append(sampler)
        self.textures.append({"name": name, "sampler": len(self.samplers) - 1,
                              "source": len(self.images) - 1})
        return len(self.textures) - 1

    # -- output -------------------------------------------------------------------------------
    def document(self):
        scene = {"name": self.name, "nodes": list(range(len(self.nodes)))}
        if self.scene_extras:
            scene["extras"] = self.scene_extras
        doc = {"asset": {"version": "2.0",
                         "generator": "Candela samples/scenes/generate_scenes.py"}}
        if self.extensions_used:
            doc["extensionsUsed"] = list(self.extensions_used)
        doc["scene"] = 0
        doc["scenes"] = [scene]
        for key, items in (("nodes", self.nodes), ("cameras", self.cameras),
                           ("meshes", self.meshes), ("materials", self.materials),
                           ("textures", self.textures), ("images", self.images),
                           ("samplers", self.samplers), ("accessors", self.accessors),
                           ("bufferViews", self.buffer_views)):
            if items:
                doc[key] = items
        doc["buffers"] = [{"uri": self.name + ".bin", "byteLength": len(self.bin)}]
        if self.lights:
            doc["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        return doc

    def write(self):
        doc = round_floats(self.document())
        with open(os.path.join(OUT_DIR, self.name + ".bin"), "wb") as f:
            f.write(bytes(self.bin))
        with open(os.path.join(OUT_DIR, self.name + ".gltf"), "w", encoding="utf-8",
                  newline="\n") as f:
            json.dump(doc, f, indent=1, sort_keys=False)
            f.write("\n")


def round_floats(value):
    if isinstance(value, float):
        return r6(value)
    if isinstance(value, list):
        return [round_floats(v) for v in value]
    if isinstance(value, dict):
        return {k: round_floats(v) for k, v in value.items()}
    return value


# ----------------------------------------------------------------------------------------------
# Scenes
# ----------------------------------------------------------------------------------------------

CORNELL_WHITE = (0.725, 0.71, 0.68)
CORNELL_RED = (0.63, 0.065, 0.05)
CORNELL_GREEN = (0.14, 0.45, 0.091)


def build_cornell_room(g):
    """The box shared by cornell_box and cornell_point: x in [-1,1], y in [0,2], z in [-1,1],
    open at +z, all walls facing inward, two white blocks."""
    white = g.material("cornell_white_diffuse", CORNELL_WHITE)
    red = g.material("cornell_red_diffuse", CORNELL_RED)
    green = g.material("cornell_green_diffuse", CORNELL_GREEN)
    x_axis, z_axis = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    g.mesh_node("floor", quad_geometry((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), x_axis, 1.0, 1.0), white)
    g.mesh_node("ceiling", quad_geometry((0.0, 2.0, 0.0), (0.0, -1.0, 0.0), x_axis, 1.0, 1.0),
                white)
    g.mesh_node("back_wall", quad_geometry((0.0, 1.0, -1.0), (0.0, 0.0, 1.0), x_axis, 1.0, 1.0),
                white)
    g.mesh_node("left_wall_red",
                quad_geometry((-1.0, 1.0, 0.0), (1.0, 0.0, 0.0), z_axis, 1.0, 1.0), red)
    g.mesh_node("right_wall_green",
                quad_geometry((1.0, 1.0, 0.0), (-1.0, 0.0, 0.0), z_axis, 1.0, 1.0), green)
    g.box_node("tall_block", (0.6, 1.2, 0.6), white, (-0.33, 0.6, -0.3), 17.0)
    g.box_node("short_block", (0.6, 0.6, 0.6), white, (0.33, 0.3, 0.35), -17.0)
    g.camera("camera_front", (0.0, 1.0, 3.4), (0.0, 1.0, 0.0), yfov=0.69)


def scene_cornell_box():
    g = GltfBuilder("cornell_box")
    build_cornell_room(g)
    light_mat = g.material("ceiling_light_emissive", (0.0, 0.0, 0.0), emissive=(1.0, 1.0, 1.0),
                           extensions={"KHR_materials_emissive_strength":
                                       {"emissiveStrength": 15.0}})
    g.mesh_node("ceiling_light",
                quad_geometry((0.0, 1.98, 0.0), (0.0, -1.0, 0.0), (1.0, 0.0, 0.0), 0.25, 0.2),
                light_mat)
    return g


def scene_cornell_point():
    g = GltfBuilder("cornell_point")
    build_cornell_room(g)
    g.light("ceiling_point_light", "point", 3.0, (0.0, 1.8, 0.0))
    return g


def scene_spheres():
    g = GltfBuilder("spheres")
    values_metallic = (0.0, 0.25, 0.5, 0.75, 1.0)
    values_roughness = (0.05, 0.25, 0.5, 0.75, 1.0)
    ground = g.material("ground_grey", (0.5, 0.5, 0.5), roughness=0.8)
    g.mesh_node("ground_plane",
                quad_geometry((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 10.0, 10.0),
                ground)
    for row, rough in enumerate(values_roughness):      # rows (y): roughness, smooth on top
        for col, metal in enumerate(values_metallic):    # columns (x): metallic, dielectric left
            mat = g.material("copper_m%.2f_r%.2f" % (metal, rough), (0.9, 0.5, 0.3),
                             metallic=metal, roughness=rough)
            center = (-2.0 + col * 1.0, 4.5 - row * 1.0, 0.0)
            g.sphere_node("sphere_metallic%.2f_roughness%.2f" % (metal, rough), center, 0.4, mat)
    g.light("sun", "directional", 3.0, (0.0, 8.0, 0.0), direction=(-0.4, -0.8, -0.45))
    g.camera("camera_front", (0.0, 2.5, 7.5), (0.0, 2.5, 0.0), yfov=0.75)
    g.scene_extras["environment_radiance"] = [0.25, 0.3, 0.4]
    return g


def scene_shadow_test():
    g = GltfBuilder("shadow_test")
    ground = g.material("ground_white_grey", (0.8, 0.8, 0.8), roughness=0.9)
    g.mesh_node("ground_plane",
                quad_geometry((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 6.0, 6.0),
                ground)
    g.box_node("box_small", (0.4, 0.4, 0.4), g.material("box_small_red", (0.7, 0.25, 0.2),
                                                        roughness=0.7),
               (1.5, 0.2, 1.3), 10.0)
    g.box_node("box_medium", (0.8, 0.8, 0.8), g.material("box_medium_green", (0.3, 0.6, 0.3),
                                                         roughness=0.7),
               (-1.7, 0.4, 0.4), 30.0)
    g.box_node("box_large", (1.6, 1.2, 0.8), g.material("box_large_blue", (0.3, 0.4, 0.7),
                                                        roughness=0.7),
               (-0.4, 0.6, -1.9), -15.0)
    grey = g.material("light_grey", (0.7, 0.7, 0.7), roughness=0.6)
    g.box_node("thin_pole", (0.05, 2.5, 0.05), grey, (-0.5, 1.25, 1.2))
    # Bottom face 1.2 m above the ground.
    g.box_node("floating_slab", (1.5, 0.1, 1.5), grey, (0.5, 1.25, 0.0), 20.0)
    g.light("spot_light", "spot", 40.0, (2.0, 5.0, 2.0), direction=(-2.0, -5.0, -2.0),
            inner_cone=0.3, outer_cone=0.5)
    g.light("sun_low_from_left", "directional", 1.5, (-5.0, 5.0, 2.0),
            direction=(0.6, -0.5, -0.3))
    g.camera("camera_front", (0.0, 4.0, 9.0), (0.0, 0.5, 0.0), yfov=0.69)
    g.scene_extras["environment_radiance"] = [0.05, 0.06, 0.08]
    return g


def scene_transparency():
    g = GltfBuilder("transparency")
    up, x_axis = (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)
    g.mesh_node("floor", quad_geometry((0.0, 0.0, 0.0), up, x_axis, 4.0, 4.0),
                g.material("floor_grey", (0.6, 0.6, 0.6), roughness=0.8))
    g.mesh_node("back_wall", quad_geometry((0.0, 2.0, -2.5), (0.0, 0.0, 1.0), x_axis, 4.0, 2.0),
                g.material("back_wall_beige", (0.75, 0.7, 0.6), roughness=0.9))
    g.box_node("white_box", (0.8, 0.8, 0.8), g.material("box_white", (0.8, 0.8, 0.8),
                                                        roughness=0.6),
               (-0.9, 0.4, -1.4), 20.0)
    g.sphere_node("magenta_sphere", (0.9, 0.5, -1.3), 0.5,
                  g.material("sphere_magenta", (0.8, 0.15, 0.45), roughness=0.4))

    # Three axis-aligned BLEND panes facing the camera, overlapping pairwise at different depths.
    pane = quad_geometry((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), x_axis, 0.4, 0.4)

    def pane_material(name, color):
        return g.material(name, color, roughness=0.5, alpha=0.5, alphaMode="BLEND",
                          doubleSided=True)

    for name, color, center in (("pane_red", (0.9, 0.1, 0.1), (-0.95, 1.3, 0.0)),
                                ("pane_green", (0.1, 0.9, 0.1), (-0.5, 1.3, 0.15)),
                                ("pane_blue", (0.1, 0.1, 0.9), (-0.725, 0.9, 0.3))):
        g.mesh_node(name, pane, pane_material(name + "_blend", color), translation=center,
                    key="pane")
    # Two panes crossing through each other along their shared vertical centre line.
    g.mesh_node("pane_interpenetrating_a", pane,
                pane_material("pane_yellow_blend", (0.9, 0.85, 0.1)),
                translation=(0.85, 1.1, 0.2), key="pane")
    g.mesh_node("pane_interpenetrating_b", pane,
                pane_material("pane_cyan_blend", (0.1, 0.85, 0.9)),
                translation=(0.85, 1.1, 0.2), rotation=quat_y(30.0), key="pane")

    # Alpha-masked fence in the foreground (texture period 0.4 m: one 16 px cell = 0.1 m).
    fence_tex = g.texture_png("fence_grid", "fence.png", fence_png(), {
        "name": "nearest_repeat", "magFilter": NEAREST, "minFilter": NEAREST, "wrapS": REPEAT, "wrapT": REPEAT})
    fence_mat = g.material("fence_mask", (1.0, 1.0, 1.0), roughness=0.7,
                           base_color_texture=fence_tex, alphaMode="MASK", alphaCutoff=0.5,
                           doubleSided=True)
    g.mesh_node("fence", quad_geometry((0.0, 0.3, 1.4), (0.0, 0.0, 1.0), x_axis, 1.6, 0.3,
                                       uv_repeat=(8.0, 1.5)), fence_mat)

    g.light("point_light", "point", 20.0, (1.5, 3.0, 2.0))
    g.camera("camera_front", (0.0, 1.4, 4.6), (0.0, 0.85, 0.0), yfov=0.75)
    g.scene_extras["environment_radiance"] = [0.3, 0.3, 0.3]
    return g


def scene_reflections():
    g = GltfBuilder("reflections")
    x_axis, z_axis = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    # Room x in [-2,2], y in [0,3], z in [-2,2]; open at +z (behind the camera).
    g.mesh_node("glossy_floor",
                quad_geometry((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), x_axis, 2.0, 2.0),
                g.material("floor_glossy_grey", (0.6, 0.6, 0.6), roughness=0.15))
    g.mesh_node("ceiling",
                quad_geometry((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), x_axis, 2.0, 2.0),
                g.material("ceiling_white", (0.8, 0.8, 0.8), roughness=0.9))
    g.mesh_node("back_wall",
                quad_geometry((0.0, 1.5, -2.0), (0.0, 0.0, 1.0), x_axis, 2.0, 1.5),
                g.material("wall_light_blue", (0.55, 0.65, 0.8), roughness=0.9))
    g.mesh_node("left_wall",
                quad_geometry((-2.0, 1.5, 0.0), (1.0, 0.0, 0.0), z_axis, 2.0, 1.5),
                g.material("wall_light_peach", (0.8, 0.62, 0.5), roughness=0.9))
    g.mesh_node("right_wall",
                quad_geometry((2.0, 1.5, 0.0), (-1.0, 0.0, 0.0), z_axis, 2.0, 1.5),
                g.material("wall_light_green", (0.6, 0.78, 0.58), roughness=0.9))

    # Each sphere carries a reflection probe at its centre whose box is the room, so lookups are
    # parallax-corrected (box-projected) onto the walls (center is in the node's space).
    def room_probe(center):
        room_center, room_half = (0.0, 1.5, 0.0), (2.0, 1.5, 2.0)
        return {"reflection_probe": {"position": [0.0, 0.0, 0.0],
                                     "center": [r - c for r, c in zip(room_center, center)],
                                     "extent": list(room_half)}}
    mirror_center = (-0.8, 0.55, -0.7)
    g.sphere_node("mirror_sphere", mirror_center, 0.55,
                  g.material("mirror_chrome", (0.95, 0.95, 0.95), metallic=1.0, roughness=0.02),
                  extras=room_probe(mirror_center))
    glass_radius = 0.4
    glass_center = (0.55, glass_radius, 0.35)
    g.sphere_node("glass_sphere", glass_center, glass_radius, g.material(
        "glass_clear", (1.0, 1.0, 1.0), metallic=0.0, roughness=0.0, extensions={
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_ior": {"ior": 1.5},
            "KHR_materials_volume": {"thicknessFactor": 2.0 * glass_radius}}),
        extras=room_probe(glass_center))
    g.box_node("orange_box", (0.5, 0.5, 0.5),
               g.material("box_orange", (0.85, 0.3, 0.08), roughness=0.5),
               (1.05, 0.25, -0.85), 25.0)

    g.light("ceiling_point_light", "point", 10.0, (0.0, 2.5, 0.2))
    g.camera("camera_front", (0.0, 1.5, 3.2), (0.0, 0.75, -0.5), yfov=0.8)
    g.scene_extras["environment_radiance"] = [0.1, 0.1, 0.1]
    return g


SCENES = (scene_cornell_box, scene_cornell_point, scene_spheres, scene_shadow_test,
          scene_transparency, scene_reflections)


# ----------------------------------------------------------------------------------------------
# Validation of the written files
# ----------------------------------------------------------------------------------------------

COMPONENT_SIZE = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
TYPE_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
KNOWN_EXTENSIONS = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                    "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"}


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def check_scene(name):
    """Re-read a written scene and check its structure; returns (triangles, node names)."""
    errors = []

    def check(cond, msg):
        if not cond:
            errors.append(msg)

    with open(os.path.join(OUT_DIR, name + ".gltf"), encoding="utf-8") as f:
        doc = json.load(f)
    check(doc["asset"]["version"] == "2.0", "asset.version")
    buf = doc["buffers"][0]
    with open(os.path.join(OUT_DIR, buf["uri"]), "rb") as f:
        data = f.read()
    check(len(doc["buffers"]) == 1 and buf["uri"] == name + ".bin", "one buffer named like scene")
    check(len(data) == buf["byteLength"], "buffer byteLength matches .bin size")
    for i, bv in enumerate(doc["bufferViews"]):
        check(bv["byteOffset"] + bv["byteLength"] <= len(data), "bufferView %d overflows" % i)
        check(bv["byteOffset"] % 4 == 0, "bufferView %d misaligned" % i)

    def read(acc_index):
        acc = doc["accessors"][acc_index]
        bv = doc["bufferViews"][acc["bufferView"]]
        size = COMPONENT_SIZE[acc["componentType"]]
        width = TYPE_WIDTH[acc["type"]]
        off = acc.get("byteOffset", 0)
        check(off % size == 0, "accessor %d misaligned" % acc_index)
        check(off + acc["count"] * size * width <= bv["byteLength"],
              "accessor %d overflows its bufferView" % acc_index)
        fmt = "<%d%s" % (acc["count"] * width, "f" if acc["componentType"] == FLOAT else "I")
        flat = struct.unpack_from(fmt, data, bv["byteOffset"] + off)
        return [flat[k:k + width] for k in range(0, len(flat), width)], acc

    triangles = 0
    used_exts = set()
    for mi, mesh in enumerate(doc["meshes"]):
        for prim in mesh["primitives"]:
            check(prim.get("mode", 4) == 4, "mesh %d mode" % mi)
            attrs = prim["attributes"]
            check("POSITION" in attrs and "NORMAL" in attrs, "mesh %d attributes" % mi)
            pos, pacc = read(attrs["POSITION"])
            nrm, _ = read(attrs["NORMAL"])
            check(len(nrm) == len(pos), "mesh %d normal count" % mi)
            for k in range(3):
                check(f32(pacc["min"][k]) == min(p[k] for p in pos), "mesh %d min" % mi)
                check(f32(pacc["max"][k]) == max(p[k] for p in pos), "mesh %d max" % mi)
            for n in nrm:
                check(abs(math.sqrt(dot(n, n)) - 1.0) < 1e-5, "mesh %d normal length" % mi)
            mat = doc["materials"][prim["material"]]
            tex = mat["pbrMetallicRoughness"].get("baseColorTexture")
            if tex is not None:
                check("TEXCOORD_0" in attrs, "mesh %d textured without TEXCOORD_0" % mi)
                check(tex["index"] < len(doc["textures"]), "mesh %d texture index" % mi)
            if "TEXCOORD_0" in attrs:
                uv, _ = read(attrs["TEXCOORD_0"])
                check(len(uv) == len(pos), "mesh %d uv count" % mi)
            idx_acc = doc["accessors"][prim["indices"]]
            check(idx_acc["componentType"] == UNSIGNED_INT and idx_acc["type"] == "SCALAR",
                  "mesh %d index type" % mi)
            idx, _ = read(prim["indices"])
            idx = [i[0] for i in idx]
            check(len(idx) % 3 == 0, "mesh %d index count" % mi)
            check(max(idx) < len(pos), "mesh %d index out of range" % mi)
            for t in range(0, len(idx), 3):
                a, b, c = (pos[i] for i in idx[t:t + 3])
                gn = cross(sub(b, a), sub(c, a))
                avg = add(add(nrm[idx[t]], nrm[idx[t + 1]]), nrm[idx[t + 2]])
                check(dot(gn, gn) > 0.0, "mesh %d degenerate triangle" % mi)
                check(dot(gn, avg) > 0.0, "mesh %d triangle %d winding" % (mi, t // 3))
            triangles += len(idx) // 3
        for ext in doc["materials"][mesh["primitives"][0]["material"]].get("extensions", {}):
            used_exts.add(ext)

    for ni, node in enumerate(doc["nodes"]):
        check(bool(node.get("name")), "node %d unnamed" % ni)
        if "rotation" in node:
            q = node["rotation"]
            check(abs(math.sqrt(sum(c * c for c in q)) - 1.0) < 1e-5, "node %d quat" % ni)
        if "mesh" in node:
            check(node["mesh"] < len(doc["meshes"]), "node %d mesh index" % ni)
        if "camera" in node:
            check(node["camera"] < len(doc["cameras"]), "node %d camera index" % ni)
        sphere = node.get("extras", {}).get("sphere")
        if sphere is not None:
            check("scale" not in node, "sphere node %d scaled" % ni)
            pos, _ = read(doc["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"])
            for p in pos:
                check(abs(math.sqrt(dot(p, p)) - sphere["radius"]) < 1e-5,
                      "sphere node %d radius" % ni)
        light = node.get("extensions", {}).get("KHR_lights_punctual")
        if light is not None:
            used_exts.add("KHR_lights_punctual")
            check(light["light"] < len(doc["extensions"]["KHR_lights_punctual"]["lights"]),
                  "node %d light index" % ni)
    for mat in doc["materials"]:
        check(bool(mat.get("name")), "unnamed material")
    check(set(doc.get("extensionsUsed", [])) == used_exts, "extensionsUsed mismatch")
    check(used_exts <= KNOWN_EXTENSIONS, "unexpected extension")
    check(doc["cameras"][0]["perspective"]["aspectRatio"] == 1.0, "camera aspect")
    check(doc["scenes"][doc["scene"]]["nodes"] == list(range(len(doc["nodes"]))), "scene nodes")
    for img in doc.get("images", []):
        with open(os.path.join(OUT_DIR, img["uri"]), "rb") as f:
            check(f.read(8) == b"\x89PNG\r\n\x1a\n", "image %s signature" % img["uri"])
    if errors:
        raise SystemExit("%s.gltf: %d problem(s), first: %s" % (name, len(errors), errors[0]))
    return triangles, [n["name"] for n in doc["nodes"]]


def main():
    total = 0
    for build in SCENES:
        g = build()
        g.write()
        triangles, _ = check_scene(g.name)
        size = len(g.bin)
        total += size
        print("%-14s %6d triangles  %7d bytes  %2d nodes" % (g.name, triangles, size,
                                                             len(g.nodes)))
    print("total binary size: %d bytes" % total)
    return 0


if __name__ == "__main__":
    sys.exit(main())
