#!/usr/bin/env python3
"""Writes the glTF test fixtures two_parts.gltf (embedded buffer) and two_parts_external.gltf
(+ two_parts.bin).

Node tree (scene 0):
  rig   (no mesh, translation (10, 0, 0))
  └─ base  (mesh "cube_mesh", rotation 90° about +z)
     └─ arm   (mesh "tetra_mesh", translation (0, 0, 2))

cube_mesh: the unit cube [0,1]³, 24 vertices (4 per face, as exporters split them by normal),
           36 u16 indices, counter-clockwise seen from outside.
tetra_mesh: the tetrahedron (0, e1, e2, e3), non-indexed, 12 vertices.
"""
import base64
import json
import math
import struct

# (outward axis, sign): quad corners in counter-clockwise order seen from outside.
FACES = [
    [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)],  # z = 0
    [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],  # z = 1
    [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)],  # y = 0
    [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)],  # y = 1
    [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)],  # x = 0
    [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)],  # x = 1
]
cube_pos = [p for face in FACES for p in face]
cube_idx = []
for f in range(6):
    b = 4 * f
    cube_idx += [b, b + 1, b + 2, b, b + 2, b + 3]

O, X, Y, Z = (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)
tetra_pos = [O, Y, X, O, X, Z, O, Z, Y, X, Y, Z]


def f32s(points):
    return b"".join(struct.pack("<3f", *p) for p in points)


cube_bytes = f32s(cube_pos)
idx_bytes = struct.pack("<%dH" % len(cube_idx), *cube_idx)
tetra_bytes = f32s(tetra_pos)
blob = cube_bytes + idx_bytes + tetra_bytes  # 288 + 72 + 144, all multiples of 4


def bounds(points):
    return [min(p[i] for p in points) for i in range(3)], [max(p[i] for p in points) for i in range(3)]


cmin, cmax = bounds(cube_pos)
tmin, tmax = bounds(tetra_pos)
s = math.sqrt(0.5)
doc = {
    "asset": {"version": "2.0", "generator": "ballast test fixture"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [
        {"name": "rig", "translation": [10.0, 0.0, 0.0], "children": [1]},
        {"name": "base", "mesh": 0, "rotation": [0.0, 0.0, s, s], "children": [2]},
        {"name": "arm", "mesh": 1, "translation": [0.0, 0.0, 2.0]},
    ],
    "meshes": [
        {"name": "cube_mesh", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]},
        {"name": "tetra_mesh", "primitives": [{"attributes": {"POSITION": 2}, "mode": 4}]},
    ],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": len(cube_pos), "type": "VEC3", "min": cmin, "max": cmax},
        {"bufferView": 1, "componentType": 5123, "count": len(cube_idx), "type": "SCALAR"},
        {"bufferView": 2, "componentType": 5126, "count": len(tetra_pos), "type": "VEC3", "min": tmin, "max": tmax},
    ],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": len(cube_bytes), "target": 34962},
        {"buffer": 0, "byteOffset": len(cube_bytes), "byteLength": len(idx_bytes), "target": 34963},
        {"buffer": 0, "byteOffset": len(cube_bytes) + len(idx_bytes), "byteLength": len(tetra_bytes), "target": 34962},
    ],
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
with open("two_parts.gltf", "w") as f:
    json.dump(doc, f, indent=2)
    f.write("\n")

doc["buffers"][0]["uri"] = "two_parts.bin"
with open("two_parts_external.gltf", "w") as f:
    json.dump(doc, f, indent=2)
    f.write("\n")
with open("two_parts.bin", "wb") as f:
    f.write(blob)
