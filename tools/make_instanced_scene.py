#!/usr/bin/env python3
"""Writes a lab YAML scene that places COUNT copies of an OBJ mesh on a ground plane, through
the `Instances` list (docs/reference.md, "Instances"): a square grid, each copy turned about the
vertical by a seeded random angle and scaled by 0.8-1.2, under a directional light, with a
camera that sees the whole grid. Beside the YAML it writes ground.obj (two triangles).

    python3 tools/make_instanced_scene.py ../shared/scenes/stanford-dragon-100k/dragon.obj \\
        --count 100 -o /tmp/forest/scene.yaml
    vkrt render /tmp/forest/scene.yaml -o forest.png

The mesh keeps its own MTL's materials (its `mtllib`), or gets a grey one with --material.
vkrt keeps the mesh once and its placements, so the count is bounded by what a 32-bit
primitive id names (2^32 - 1 triangles, every copy counted: vkrt says so with the count): 10,000
copies of a 100k-triangle mesh, a billion triangles, load and render on a laptop."""
import argparse
import math
import os
import random
import sys


def bounds(obj_path):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    with open(obj_path, "rb") as f:
        for line in f:
            if line.startswith(b"v "):
                xyz = [float(v) for v in line.split()[1:4]]
                lo = [min(a, b) for a, b in zip(lo, xyz)]
                hi = [max(a, b) for a, b in zip(hi, xyz)]
    if lo[0] == math.inf:
        sys.exit(f"{obj_path}: no vertices (lines 'v x y z')")
    return lo, hi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh", help="an OBJ file")
    ap.add_argument("--count", type=int, default=100, help="copies of the mesh (default 100)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the angles and scales (default 1)")
    ap.add_argument("--material", action="store_true", help="one grey material instead of the mesh's MTL")
    ap.add_argument("-o", "--output", required=True, help="the YAML file to write")
    a = ap.parse_args()
    if a.count < 1:
        sys.exit("--count must be at least 1")
    lo, hi = bounds(a.mesh)
    size = [h - l for l, h in zip(lo, hi)]
    footprint = max(size[0], size[2], 1e-6)
    # A copy turned by 45 degrees and scaled by 1.2 spans 1.2 * sqrt(2) = 1.7 footprints.
    spacing = 1.75 * footprint
    side = math.ceil(math.sqrt(a.count))
    extent = side * spacing
    rng = random.Random(a.seed)
    out_dir = os.path.dirname(os.path.abspath(a.output))
    os.makedirs(out_dir, exist_ok=True)
    mesh = os.path.relpath(os.path.abspath(a.mesh), out_dir)
    # The ground: a square under the grid, at the mesh's lowest point.
    g, y0 = extent, lo[1]
    with open(os.path.join(out_dir, "ground.obj"), "w") as f:
        f.write(f"v {-0.1 * g} 0 {-0.1 * g}\nv {1.1 * g} 0 {-0.1 * g}\nv {1.1 * g} 0 {1.1 * g}\nv {-0.1 * g} 0 {1.1 * g}\n")
        f.write("vn 0 1 0\nf 1//1 4//1 3//1\nf 1//1 3//1 2//1\n")
    centre = [0.5 * extent, 0.0, 0.5 * extent]
    eye = [centre[0], 0.6 * extent + 2 * size[1], centre[2] - 1.1 * extent]
    lines = [
        "# Written by tools/make_instanced_scene.py: %d copies of %s." % (a.count, os.path.basename(a.mesh)),
        "Cameras:",
        "  - Eye: [%g, %g, %g]" % tuple(eye),
        "    Target: [%g, %g, %g]" % (centre[0], 0.5 * size[1], centre[2]),
        "    Up: [0, 1, 0]",
        "    Fovy: 45",
        "Lights:",
        "  - Type: Directional",
        "    Direction: [0.4, 1, -0.3]",
        "    Intensity: [1, 1, 1]",
        "Materials:",
        "  - Name: ground",
        "    Diffuse: [0.5, 0.5, 0.5]",
        "  - Name: grey",
        "    Diffuse: [0.7, 0.7, 0.7]",
        "Models:",
        "  - Mesh: ground.obj",
        "    Material: ground",
        "Instances:",
        "  - Mesh: %s" % mesh,
    ]
    if a.material:
        lines.append("    Material: grey")
    lines.append("    Transforms:")
    # Each copy: its footprint's centre on a grid cell's centre, its base on the ground.
    cx, cz = 0.5 * (lo[0] + hi[0]), 0.5 * (lo[2] + hi[2])
    for i in range(a.count):
        s = rng.uniform(0.8, 1.2)
        angle = rng.uniform(0.0, 360.0)
        x = (i % side + 0.5) * spacing
        z = (i // side + 0.5) * spacing
        # Scale, then turn about y, then move: the footprint's centre goes to (x, z) and the
        # lowest point to the ground (y = 0).
        r = math.radians(angle)
        ox = math.cos(r) * cx * s + math.sin(r) * cz * s
        oz = -math.sin(r) * cx * s + math.cos(r) * cz * s
        lines.append("      - {Scale: %.4f, Rotation: [0, %.3f, 0], Translation: [%g, %g, %g]}" % (s, angle, x - ox, -y0 * s + 0.0, z - oz))
    with open(a.output, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"{a.output}: {a.count} copies of {a.mesh} on a {side}x{side} grid, {spacing:g} apart", file=sys.stderr)


if __name__ == "__main__":
    main()
