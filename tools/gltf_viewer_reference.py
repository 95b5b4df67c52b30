#!/usr/bin/env python3
"""Renders scenes/gltf/showcase.gltf with an independent glTF viewer, pyrender (OpenGL
rasteriser, metallic-roughness PBR) on Mesa's software OSMesa/llvmpipe, for comparison with
vkrt's render of the same file. Writes docs/images/gltf-viewer.png (640x480).

Installs (nothing in the repository):
    apt-get install libosmesa6                 # Debian 12: 22.3.6-1+deb12u2
    python3 -m venv /tmp/gltfview-venv
    /tmp/gltfview-venv/bin/pip install pyrender==0.1.45 trimesh==5.2.0 PyOpenGL==3.1.7 \\
        numpy==1.26.4 pillow==13.0.0
    (pyrender pins PyOpenGL==3.1.0, whose OSMesa binding cannot make the core-profile context
    pyrender needs; pip warns about the pin, which is expected. pyrender 0.1.45 uses np.infty,
    gone in NumPy 2, hence numpy 1.26.4. pip also brings scipy, networkx, pyglet, imageio,
    freetype-py, six.)

Run (from the repository root):
    PYOPENGL_PLATFORM=osmesa /tmp/gltfview-venv/bin/python tools/gltf_viewer_reference.py

Options: --out PATH, --width/--height (640x480), --exposure EV (scales every light and the
emission by 2^EV; pyrender itself only clamps and applies gamma 1/2.2), --shadows
(both|spot|directional|none; default both), --raw
(skip the emission fix below, i.e. pyrender exactly as it reads the file).

What comes from the viewer's own loader (trimesh's glTF importer, pyrender.Mesh.from_trimesh):
geometry, the node hierarchy, normals, UVs, base colour / normal / metallicRoughness textures
and the material factors. What this script adds by hand, read from the file's JSON:
  - the camera: pose = world matrix of node "camera", yfov and aspectRatio of its camera,
    znear (pyrender has no infinite far plane; zfar = 100);
  - the three KHR_lights_punctual lights (trimesh ignores the extension): pyrender's
    DirectionalLight / PointLight / SpotLight at the world matrix of their nodes (all shine
    along local -Z as in glTF), with the file's colour, intensity (pyrender's units are the
    same: candela for point/spot, lux for directional, shaded with BRDF * N.L) and cone angles;
  - KHR_materials_emissive_strength (ignored by trimesh): emissiveFactor * emissiveStrength;
  - one fix for a pyrender 0.1.45 shader bug (mesh.frag multiplies the emission by
    emissiveFactor twice): the factor given to it is the square root of the wanted one.
    (metallicRoughnessTexture needs none: pyrender uploads its G and B channels as the
    texture's R and G, which its shader reads as roughness and metallic.)
"""
import argparse
import json
import math
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "gltf", "showcase.gltf")
OUT = os.path.join(ROOT, "docs", "images", "gltf-viewer.png")


def node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    r = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    m = np.eye(4)
    m[:3, :3] = r * s
    m[:3, 3] = t
    return m


def world_matrices(gltf):
    """World matrix of every node reachable from the default scene."""
    out = {}

    def walk(i, parent):
        m = parent @ node_matrix(gltf["nodes"][i])
        out[i] = m
        for c in gltf["nodes"][i].get("children", []):
            walk(c, m)

    for root in gltf["scenes"][gltf.get("scene", 0)]["nodes"]:
        walk(root, np.eye(4))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--exposure", type=float, default=0.0)
    ap.add_argument("--shadows", choices=["both", "spot", "directional", "none"], default="both",
                    help="pyrender's shadow maps (it has none for point lights)")
    ap.add_argument("--raw", action="store_true")
    args = ap.parse_args()

    os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
    import pyrender
    import trimesh
    from PIL import Image

    with open(args.scene) as f:
        gltf = json.load(f)
    world = world_matrices(gltf)
    gain = 2.0 ** args.exposure

    # Geometry and materials through the viewer's loader.
    tscene = trimesh.load(args.scene, force="scene", process=False)
    by_name = {m.get("name"): m for m in gltf.get("materials", [])}
    scene = pyrender.Scene(bg_color=[0.0, 0.0, 0.0, 1.0], ambient_light=[0.0, 0.0, 0.0])
    meshes = {}
    for gname, geom in tscene.geometry.items():
        mat = geom.visual.material
        src = by_name.get(getattr(mat, "name", None), {})
        emissive = np.array(src.get("emissiveFactor", [0.0, 0.0, 0.0]), dtype=np.float64)
        emissive *= src.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        emissive *= gain
        if not args.raw:
            emissive = np.sqrt(emissive)
        mat.emissiveFactor = emissive
        meshes[gname] = pyrender.Mesh.from_trimesh(geom, smooth=True)
    for node in tscene.graph.nodes_geometry:
        pose, gname = tscene.graph[node]
        scene.add(meshes[gname], pose=pose, name=node)

    # Camera and lights from the JSON.
    cam_node = next(i for i, n in enumerate(gltf["nodes"]) if n.get("name") == "camera" and "camera" in n)
    persp = gltf["cameras"][gltf["nodes"][cam_node]["camera"]]["perspective"]
    camera = pyrender.PerspectiveCamera(yfov=persp["yfov"], znear=persp.get("znear", 0.05),
                                        zfar=persp.get("zfar", 100.0),
                                        aspectRatio=persp.get("aspectRatio", args.width / args.height))
    scene.add(camera, pose=world[cam_node], name="camera")

    lights = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for i, n in enumerate(gltf["nodes"]):
        ext = n.get("extensions", {}).get("KHR_lights_punctual")
        if ext is None or i not in world:
            continue
        L = lights[ext["light"]]
        color = L.get("color", [1.0, 1.0, 1.0])
        intensity = L.get("intensity", 1.0) * gain
        if L["type"] == "directional":
            light = pyrender.DirectionalLight(color=color, intensity=intensity)
        elif L["type"] == "point":
            light = pyrender.PointLight(color=color, intensity=intensity)
        elif L["type"] == "spot":
            spot = L.get("spot", {})
            light = pyrender.SpotLight(color=color, intensity=intensity,
                                       innerConeAngle=spot.get("innerConeAngle", 0.0),
                                       outerConeAngle=spot.get("outerConeAngle", math.pi / 4))
        else:
            continue
        scene.add(light, pose=world[i], name=n.get("name"))
        print(f"light {n.get('name')!r}: {L['type']} intensity {intensity:g} at "
              f"{np.round(world[i][:3, 3], 3).tolist()} dir {np.round(-world[i][:3, 2], 3).tolist()}")

    flags = pyrender.RenderFlags.NONE
    if args.shadows in ("both", "directional"):
        flags |= pyrender.RenderFlags.SHADOWS_DIRECTIONAL
    if args.shadows in ("both", "spot"):
        flags |= pyrender.RenderFlags.SHADOWS_SPOT
    renderer = pyrender.OffscreenRenderer(args.width, args.height)
    color, _ = renderer.render(scene, flags=flags)
    renderer.delete()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    Image.fromarray(color).save(args.out)
    print(f"wrote {args.out} ({args.width}x{args.height}, pyrender {pyrender.__version__}, "
          f"trimesh {trimesh.__version__})")


if __name__ == "__main__":
    sys.exit(main())
