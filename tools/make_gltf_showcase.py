#!/usr/bin/env python3
"""Writes scenes/gltf/showcase.gltf (+ .bin and PNG textures): the README's glTF scene.

A small room that uses what vkrt's glTF loader reads, so that one render shows it all:
  - a floor with a base-colour texture (checker tiles) and a tangent-space normal map (bevelled
    tile edges), no tangents in the file (vkrt makes MikkTSpace ones), UVs repeating 4x;
  - a polished gold sphere (metallic 1, roughness 0.15: Whitted mirrors it), a red dielectric sphere (roughness 0.35),
    a cube under a rotated parent node whose metallicRoughnessTexture stripes it metal and
    rough (blue = metallic, green = roughness, glTF 2.0 section 3.9.2);
  - an emissive panel with KHR_materials_emissive_strength;
  - KHR_lights_punctual: a spot light, a point light and a directional light;
  - a perspective camera.
Everything here is generated, so the files are ours (same licence as vkrt).

Usage: tools/make_gltf_showcase.py [OUT_DIR]   (default scenes/gltf)
Only the Python standard library is used; the output is the same bytes on every run.
"""
import json
import math
import os
import struct
import sys
import zlib


def png_bytes(width, height, rgba_rows):
    """An 8-bit RGBA PNG from rows of (r, g, b, a) tuples, top row first."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rgba_rows)

    def chunk(tag, data):
        body = tag + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def floor_textures(n=256, tiles=2):
    """Base colour (two warm tones in a checker of `tiles` x `tiles` per texture) and the
    normal map of the same tiles with bevelled edges: each tile's border slopes down into the
    grout, the normal leaning away from the tile centre."""
    colour, normal = [], []
    size = n // tiles
    bevel = size * 0.12
    for y in range(n):
        crow, nrow = [], []
        for x in range(n):
            tx, ty = x // size, y // size
            light = (tx + ty) % 2 == 0
            crow.append((214, 196, 168, 255) if light else (120, 86, 62, 255))
            # Distances to the tile's edges, in texels.
            fx, fy = x % size + 0.5, y % size + 0.5
            nx = ny = 0.0
            if fx < bevel:
                nx = -0.6
            elif fx > size - bevel:
                nx = 0.6
            # Image rows go down while v goes up: a slope toward the top edge leans to +v.
            if fy < bevel:
                ny = 0.6
            elif fy > size - bevel:
                ny = -0.6
            l = math.sqrt(nx * nx + ny * ny + 1.0)
            v = (nx / l, ny / l, 1.0 / l)
            nrow.append(tuple(int(round((c * 0.5 + 0.5) * 255)) for c in v) + (255,))
        colour.append(crow)
        normal.append(nrow)
    return colour, normal


def stripes_texture(n=64, stripes=4):
    """metallicRoughness: stripes alternate polished metal (B 255, G 40) and rough
    dielectric (B 0, G 200)."""
    rows = []
    for y in range(n):
        metal = (y * stripes // n) % 2 == 0
        rows.append([(0, 40, 255, 255) if metal else (0, 200, 0, 255)] * n)
    return rows


class Builder:
    def __init__(self):
        self.bin = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": "vkrt tools/make_gltf_showcase.py"},
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
            "buffers": [], "bufferViews": [], "accessors": [], "meshes": [], "nodes": [],
            "materials": [], "textures": [], "images": [], "samplers": [], "cameras": [],
            "scenes": [], "extensions": {"KHR_lights_punctual": {"lights": []}},
        }

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.bin += data
        self.doc["bufferViews"].append(v)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, kind, with_bounds=False):
        width = {"VEC2": 2, "VEC3": 3, "SCALAR": 1}[kind]
        if kind == "SCALAR":
            data = struct.pack("<%dI" % len(values), *values)
            a = {"bufferView": self.view(data, 34963), "componentType": 5125, "count": len(values), "type": kind}
        else:
            flat = [c for v in values for c in v]
            data = struct.pack("<%df" % len(flat), *flat)
            a = {"bufferView": self.view(data, 34962), "componentType": 5126, "count": len(values), "type": kind}
            if with_bounds:
                a["min"] = [min(v[k] for v in values) for k in range(width)]
                a["max"] = [max(v[k] for v in values) for k in range(width)]
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def mesh(self, name, positions, normals, uvs, indices, material):
        attributes = {"POSITION": self.accessor(positions, "VEC3", True), "NORMAL": self.accessor(normals, "VEC3")}
        if uvs is not None:
            attributes["TEXCOORD_0"] = self.accessor(uvs, "VEC2")
        prim = {"attributes": attributes, "indices": self.accessor(indices, "SCALAR"), "material": material}
        self.doc["meshes"].append({"name": name, "primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def node(self, **fields):
        self.doc["nodes"].append(fields)
        return len(self.doc["nodes"]) - 1

    def material(self, **fields):
        self.doc["materials"].append(fields)
        return len(self.doc["materials"]) - 1

    def texture(self, uri, sampler=0):
        self.doc["images"].append({"uri": uri})
        self.doc["textures"].append({"source": len(self.doc["images"]) - 1, "sampler": sampler})
        return len(self.doc["textures"]) - 1

    def light(self, **fields):
        lights = self.doc["extensions"]["KHR_lights_punctual"]["lights"]
        lights.append(fields)
        return len(lights) - 1


def quad(size_x, size_z, uv_repeat):
    """A quad in the y = 0 plane facing +y, centred on the origin."""
    hx, hz = size_x / 2, size_z / 2
    p = [(-hx, 0, hz), (hx, 0, hz), (hx, 0, -hz), (-hx, 0, -hz)]
    n = [(0, 1, 0)] * 4
    uv = [(0, uv_repeat), (uv_repeat, uv_repeat), (uv_repeat, 0), (0, 0)]
    return p, n, uv, [0, 1, 2, 0, 2, 3]


def sphere(radius, segments=64, rings=32):
    p, n, uv, idx = [], [], [], []
    for j in range(rings + 1):
        theta = math.pi * j / rings
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            d = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            p.append(tuple(radius * c for c in d))
            n.append(d)
            uv.append((i / segments, j / rings))
    for j in range(rings):
        for i in range(segments):
            a = j * (segments + 1) + i
            b = a + segments + 1
            if j != 0:
                idx += [a, b, a + 1]
            if j != rings - 1:
                idx += [a + 1, b, b + 1]
    return p, n, uv, idx


def cube(half):
    p, n, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (1, -1):
            normal = [0, 0, 0]
            normal[axis] = sign
            u_axis, v_axis = [(1, 2), (2, 0), (0, 1)][axis]
            base = len(p)
            for (su, sv) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                c = [0.0, 0.0, 0.0]
                c[axis] = sign * half
                c[u_axis] = su * half * sign
                c[v_axis] = sv * half
                p.append(tuple(c))
                n.append(tuple(normal))
                uv.append(((su + 1) / 2, (sv + 1) / 2))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return p, n, uv, idx


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "scenes", "gltf")
    os.makedirs(out, exist_ok=True)
    colour, normal = floor_textures()
    with open(os.path.join(out, "floor_basecolor.png"), "wb") as f:
        f.write(png_bytes(256, 256, colour))
    with open(os.path.join(out, "floor_normal.png"), "wb") as f:
        f.write(png_bytes(256, 256, normal))
    with open(os.path.join(out, "stripes_metallic_roughness.png"), "wb") as f:
        f.write(png_bytes(64, 64, stripes_texture()))

    b = Builder()
    b.doc["samplers"].append({"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497})
    floor_tex = b.texture("floor_basecolor.png")
    floor_nrm = b.texture("floor_normal.png")
    stripes = b.texture("stripes_metallic_roughness.png")

    floor_m = b.material(name="tiles", pbrMetallicRoughness={
        "baseColorTexture": {"index": floor_tex}, "metallicFactor": 0.0, "roughnessFactor": 0.55},
        normalTexture={"index": floor_nrm, "scale": 1.0})
    wall_m = b.material(name="wall", pbrMetallicRoughness={"baseColorFactor": [0.72, 0.74, 0.78, 1], "metallicFactor": 0.0, "roughnessFactor": 0.9})
    gold_m = b.material(name="gold", pbrMetallicRoughness={"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.15})
    red_m = b.material(name="red plastic", pbrMetallicRoughness={"baseColorFactor": [0.75, 0.06, 0.05, 1], "metallicFactor": 0.0, "roughnessFactor": 0.35})
    striped_m = b.material(name="striped", pbrMetallicRoughness={
        "baseColorFactor": [0.9, 0.9, 0.92, 1], "metallicRoughnessTexture": {"index": stripes}, "metallicFactor": 1.0, "roughnessFactor": 1.0})
    glow_m = b.material(name="glow", pbrMetallicRoughness={"baseColorFactor": [0.1, 0.1, 0.1, 1], "metallicFactor": 0.0, "roughnessFactor": 1.0},
                        emissiveFactor=[1.0, 0.55, 0.2], extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}})

    floor = b.mesh("floor", *quad(8.0, 8.0, 4.0), floor_m)
    wall = b.mesh("wall", *quad(8.0, 4.0, 1.0), wall_m)
    ball = b.mesh("sphere", *sphere(0.5), gold_m)
    b.doc["meshes"].append({"name": "red sphere", "primitives": [dict(b.doc["meshes"][ball]["primitives"][0], material=red_m)]})
    red_ball = len(b.doc["meshes"]) - 1
    box = b.mesh("cube", *cube(0.35), striped_m)
    glow = b.mesh("panel", *quad(0.8, 0.25, 1.0), glow_m)

    nodes = [
        b.node(name="floor", mesh=floor),
        # The wall stands at z = -2.5: the quad turned a quarter about +x to face +z.
        b.node(name="wall", mesh=wall, translation=[0, 2.0, -2.5], rotation=[math.sin(math.pi / 4), 0, 0, math.cos(math.pi / 4)]),
        b.node(name="gold sphere", mesh=ball, translation=[-0.9, 0.5, 0.0]),
        b.node(name="red sphere", mesh=red_ball, translation=[0.25, 0.5, 0.8]),
    ]
    # The cube under a parent turned 30 degrees about +y: the hierarchy at work.
    cube_node = b.node(name="cube", mesh=box, translation=[0, 0.35, 0])
    half = math.radians(30) / 2
    nodes.append(b.node(name="cube parent", children=[cube_node], translation=[1.55, 0, -0.5], rotation=[0, math.sin(half), 0, math.cos(half)]))
    # The panel on the wall, facing the room.
    nodes.append(b.node(name="glowing panel", mesh=glow, translation=[-0.2, 1.7, -2.49], rotation=[math.sin(math.pi / 4), 0, 0, math.cos(math.pi / 4)]))

    # Lights point along their node's -z. The spot looks down at the spheres from above the camera.
    spot = b.light(type="spot", color=[1.0, 0.95, 0.85], intensity=60.0, spot={"innerConeAngle": 0.35, "outerConeAngle": 0.6})
    look_down = math.radians(-60) / 2
    nodes.append(b.node(name="spot", translation=[0.0, 3.6, 2.0], rotation=[math.sin(look_down), 0, 0, math.cos(look_down)],
                        extensions={"KHR_lights_punctual": {"light": spot}}))
    point = b.light(type="point", color=[0.6, 0.75, 1.0], intensity=6.0)
    nodes.append(b.node(name="fill", translation=[2.5, 2.2, 1.5], extensions={"KHR_lights_punctual": {"light": point}}))
    sun = b.light(type="directional", color=[1.0, 0.98, 0.95], intensity=0.6)
    # The sun from the upper left, behind the camera: -z turned down 50 degrees, then 35 about +y.
    q_pitch = (math.sin(math.radians(-50) / 2), 0, 0, math.cos(math.radians(-50) / 2))
    q_yaw = (0, math.sin(math.radians(-35) / 2), 0, math.cos(math.radians(-35) / 2))
    x1, y1, z1, w1 = q_yaw
    x2, y2, z2, w2 = q_pitch
    q = [w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2]
    nodes.append(b.node(name="sun", rotation=q, extensions={"KHR_lights_punctual": {"light": sun}}))

    # The camera at (0, 1.5, 4.2) looking 12 degrees down (along its -z).
    b.doc["cameras"].append({"type": "perspective", "perspective": {"yfov": 0.75, "znear": 0.05, "aspectRatio": 4 / 3}})
    tilt = math.radians(-12) / 2
    nodes.append(b.node(name="camera", camera=0, translation=[0.0, 1.5, 4.2], rotation=[math.sin(tilt), 0, 0, math.cos(tilt)]))

    b.doc["scenes"].append({"name": "showcase", "nodes": nodes})
    b.doc["scene"] = 0
    b.doc["buffers"].append({"uri": "showcase.bin", "byteLength": len(b.bin)})
    with open(os.path.join(out, "showcase.bin"), "wb") as f:
        f.write(bytes(b.bin))
    with open(os.path.join(out, "showcase.gltf"), "w") as f:
        json.dump(b.doc, f, indent=1)
        f.write("\n")
    print(f"wrote {out}/showcase.gltf ({len(b.doc['meshes'])} meshes, {len(b.bin)} bytes of buffer)")


if __name__ == "__main__":
    main()
