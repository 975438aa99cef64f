#!/usr/bin/python3
"""Writes tests/fuzz/seeds/*.glb: small sample scenes packed as binary glTF (JSON chunk + BIN
chunk), so that the fuzzer mutates vertex and index data as well as the JSON. Run from this folder;
the .glb files are committed, this script says how they were made."""
import json
import struct

for name in ["cornell_box", "cornell_point", "shadow_test"]:
    d = json.load(open(f"../../samples/scenes/{name}.gltf"))
    binary = open(f"../../samples/scenes/{name}.bin", "rb").read()
    d["buffers"] = [{"byteLength": len(binary)}]
    j = json.dumps(d, separators=(",", ":")).encode()
    j += b" " * ((4 - len(j) % 4) % 4)
    binary += b"\0" * ((4 - len(binary) % 4) % 4)
    body = struct.pack("<II", len(j), 0x4E4F534A) + j + struct.pack("<II", len(binary), 0x004E4942) + binary
    open(f"seeds/{name}.glb", "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)

# Compressed and instanced geometry, so that the fuzzer mutates Draco and meshopt streams and
# instance accessors: Box-Draco packed into a .glb (its Box.bin as the BIN chunk), and the two
# self-contained .glb models copied.
import shutil

d = json.load(open("../data/models/Box-Draco/Box.gltf"))
binary = open("../data/models/Box-Draco/Box.bin", "rb").read()
d["buffers"] = [{"byteLength": len(binary)}]
j = json.dumps(d, separators=(",", ":")).encode()
j += b" " * ((4 - len(j) % 4) % 4)
binary += b"\0" * ((4 - len(binary) % 4) % 4)
body = struct.pack("<II", len(j), 0x4E4F534A) + j + struct.pack("<II", len(binary), 0x004E4942) + binary
open("seeds/draco_box.glb", "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
shutil.copyfile("../data/models/BoxMeshopt/BoxMeshopt.glb", "seeds/meshopt_box.glb")
shutil.copyfile("../data/models/SimpleInstancing/SimpleInstancing.glb", "seeds/instancing.glb")
