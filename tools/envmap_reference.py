#!/usr/bin/env python3
"""Makes the environment-map reference of tests/refs (tests/path_envmap.rs): the map
`envmap-sun.exr` (a sky gradient with a small bright sun), and Mitsuba 3's render of
scenes/envmap/envmap-scene.obj lit by it alone (`envmap` emitter, identity transform: the
convention vkrt follows), with the settings in `envmap-256.json`.

    pip install mitsuba numpy   (and apt-get install libllvm19 for the llvm variant)
    python3 tools/envmap_reference.py --spp 4096            # writes tests/refs/envmap-*
    python3 tools/envmap_reference.py --view-check out.exr  # the map seen directly, no geometry

The camera and image size are the test's; the noise estimate compares the even and odd passes,
as tests/refs/cornell-256.json does.
"""
import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REFS = os.path.join(ROOT, "tests", "refs")
MAP_W, MAP_H = 128, 64
# The sun: direction by Mitsuba's (u, v) and angular radius; a smooth cosine rim so that
# texel-interpolation details barely change its power.
SUN_U, SUN_V, SUN_RADIUS_DEG, SUN_RADIANCE = 0.3, 55.0 / 180.0, 5.0, 400.0
CAMERA = {"eye": [3.0, 2.2, 4.5], "target": [0.0, 0.4, 0.0], "up": [0.0, 1.0, 0.0], "fov": 40.0}
SIZE = 256


def uv_to_dir(u, v):
    theta, phi = v * math.pi, u * 2.0 * math.pi
    return np.array([math.sin(phi) * math.sin(theta), math.cos(theta), -math.cos(phi) * math.sin(theta)])


def make_map():
    """Texel (i, j) looks along (u, v) = ((i + 0.5) / W, j / (H - 1)) (Mitsuba's eval)."""
    sun = uv_to_dir(SUN_U, SUN_V)
    img = np.zeros((MAP_H, MAP_W, 3), dtype=np.float32)
    for j in range(MAP_H):
        for i in range(MAP_W):
            d = uv_to_dir((i + 0.5) / MAP_W, j / (MAP_H - 1))
            if d[1] >= 0:
                sky = np.array([0.35, 0.55, 1.0]) * (0.4 + 0.6 * d[1]) + np.array([0.5, 0.45, 0.4]) * (1 - d[1]) ** 4
            else:
                sky = np.array([0.25, 0.22, 0.18]) * (1.0 + d[1] * 0.5)
            angle = math.degrees(math.acos(max(-1.0, min(1.0, float(d @ sun)))))
            if angle < SUN_RADIUS_DEG:
                sky = sky + SUN_RADIANCE * np.array([1.0, 0.9, 0.75]) * math.cos(0.5 * math.pi * angle / SUN_RADIUS_DEG) ** 2
            img[j, i] = sky
    return img


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=4096)
    ap.add_argument("--pass-spp", type=int, default=64)
    ap.add_argument("--view-check", metavar="OUT", help="render the map seen directly (no geometry) to OUT and stop")
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    map_path = os.path.join(REFS, "envmap-sun.exr")
    mi.Bitmap(make_map()).write(map_path)
    sensor = {
        "type": "perspective", "fov": CAMERA["fov"], "fov_axis": "y",
        "to_world": mi.ScalarTransform4f().look_at(origin=CAMERA["eye"], target=CAMERA["target"], up=CAMERA["up"]),
        "film": {"type": "hdrfilm", "width": SIZE, "height": SIZE, "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": "independent"},
    }
    scene = {"type": "scene", "integrator": {"type": "path", "max_depth": -1, "rr_depth": 5}, "sensor": sensor,
             "sky": {"type": "envmap", "filename": map_path}}
    if args.view_check:
        sensor["to_world"] = mi.ScalarTransform4f().look_at(origin=[0, 0.5, -10], target=[0.3, 0.75, -11], up=[0, 1, 0])
        sensor["fov"] = 90.0
        scene["integrator"] = {"type": "path", "max_depth": 1}
        mi.Bitmap(mi.render(mi.load_dict(scene), spp=64)).write(args.view_check)
        return
    mtl = {"ground": [0.5, 0.5, 0.5], "block": [0.7, 0.4, 0.2]}
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    from path_time_to_error import split_obj_by_material
    work = os.path.join(ROOT, "target", "envmap-reference")
    os.makedirs(work, exist_ok=True)
    for name, path in split_obj_by_material(os.path.join(ROOT, "scenes", "envmap", "envmap-scene.obj"), work).items():
        scene[name] = {"type": "obj", "filename": path, "face_normals": True,
                       "bsdf": {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": mtl[name]}}}}
    loaded = mi.load_dict(scene)
    passes = args.spp // args.pass_spp
    even, odd = np.zeros((SIZE, SIZE, 3)), np.zeros((SIZE, SIZE, 3))
    t0 = time.time()
    for p in range(passes):
        img = np.array(mi.render(loaded, spp=args.pass_spp, seed=p), dtype=np.float64)
        (even if p % 2 == 0 else odd)[:] += img
    seconds = time.time() - t0
    a, b = even / ((passes + 1) // 2), odd / (passes // 2)
    ref = (even + odd) / passes
    mi.Bitmap(ref.astype(np.float32)).write(os.path.join(REFS, "envmap-256.exr"))
    meta = {
        "mitsuba": mi.__version__, "variant": "llvm_ad_rgb", "cpu": platform.machine(),
        "obj": "scenes/envmap/envmap-scene.obj", "materials": mtl, "envmap": "tests/refs/envmap-sun.exr",
        "envmap_size": [MAP_W, MAP_H], "sun": {"u": SUN_U, "v": SUN_V, "radius_deg": SUN_RADIUS_DEG, "radiance": SUN_RADIANCE},
        "eye": CAMERA["eye"], "target": CAMERA["target"], "up": CAMERA["up"], "fov_y_deg": CAMERA["fov"],
        "width": SIZE, "height": SIZE, "max_depth": -1, "rr_depth": 5, "sampler": "independent", "twosided": True,
        "rfilter": "box", "integrator": "path", "spp": passes * args.pass_spp, "pass_spp": args.pass_spp,
        "render_seconds": round(seconds, 3),
        "noise_estimate": {
            "relmse_of_ref_vs_truth": float(np.mean((a - b) ** 2 / (ref ** 2 + 1e-2)) / 4),
            "how": "even vs odd passes A,B: mean((A-B)^2/(ref^2+1e-2))/4",
        },
        "mean_rgb": [float(x) for x in ref.reshape(-1, 3).mean(axis=0)],
    }
    with open(os.path.join(REFS, "envmap-256.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print(json.dumps(meta, indent=1))


if __name__ == "__main__":
    main()
