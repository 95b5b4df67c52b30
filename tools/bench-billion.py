#!/usr/bin/env python3
"""A billion instanced triangles (issue 44): 10,000 copies of the 100k-triangle Happy Buddha
(../shared/scenes/happy-buddha-100k) on a ground plane, turned and scaled, written by
tools/make_instanced_scene.py, rendered by `vkrt render --cache off -v`: a 1024x768 Whitted
frame and a 64-spp path frame (--path-size, default 1024x768). Prints a Markdown table of
medians over ROUNDS: load, BVH build, upload, their sum, render seconds, the device arrays' MiB
(`render -v`) and the process's peak resident memory. With --mitsuba PYTHON (an interpreter with
PyPI mitsuba; Debian's libllvm19 for llvm_ad_rgb), the anchor in the same rounds: Mitsuba 3
loading the same copies as one `shapegroup` and 10,000 `instance`s, then its path frame.

    python3 tools/bench-billion.py [--rounds 1] [--count 10000] [--vkrt target/release/vkrt] [--mitsuba PYTHON]
"""
import argparse
import importlib.util
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MESH = os.path.normpath(os.path.join(ROOT, "../shared/scenes/happy-buddha-100k/buddha.obj"))


def run(vkrt, scene, out, extra):
    """tools/bench-instancing.py's run, and load + build + upload."""
    spec = importlib.util.spec_from_file_location("bench_instancing", os.path.join(ROOT, "tools/bench-instancing.py"))
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    r = bench.run(vkrt, scene, out, extra)
    r["prepare"] = r["load"] + r["build"] + r["upload"]
    return r


def mitsuba_child(yaml_path, size, out):
    """Runs in the Mitsuba interpreter: the YAML's camera, light, ground and copies as a
    shapegroup with one instance per transform; prints JSON times."""
    import time
    import mitsuba as mi
    import numpy as np
    mi.set_variant("llvm_ad_rgb")
    text = open(yaml_path).read()
    vec = lambda key: [float(v) for v in re.search(key + r": \[([^\]]*)\]", text).group(1).split(",")]
    width, height = (int(v) for v in size.split("x"))
    grey = lambda v: {"type": "diffuse", "reflectance": {"type": "rgb", "value": [v, v, v]}}
    mesh = os.path.normpath(os.path.join(os.path.dirname(yaml_path), re.search(r"Instances:\n  - Mesh: (\S+)", text).group(1)))
    scene = {
        "type": "scene",
        "integrator": {"type": "path"},
        "sensor": {
            "type": "perspective", "fov": float(re.search(r"Fovy: ([\d.]+)", text).group(1)), "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=vec("Eye"), target=vec("Target"), up=vec("Up")),
            "film": {"type": "hdrfilm", "width": width, "height": height},
        },
        # The lab format's Direction points toward the light; Mitsuba's along its rays.
        "sun": {"type": "directional", "direction": [-v for v in vec("Direction")], "irradiance": {"type": "rgb", "value": [1, 1, 1]}},
        "ground": {"type": "obj", "filename": os.path.join(os.path.dirname(yaml_path), "ground.obj"), "bsdf": grey(0.5)},
        "buddha": {"type": "shapegroup", "mesh": {"type": "obj", "filename": mesh, "bsdf": grey(0.7)}},
    }
    pattern = r"\{Scale: ([\d.]+), Rotation: \[0, ([\d.]+), 0\], Translation: \[([^\]]*)\]\}"
    for k, (s, a, t) in enumerate(re.findall(pattern, text)):
        to_world = mi.ScalarTransform4f().translate([float(v) for v in t.split(",")]).rotate([0, 1, 0], float(a)).scale(float(s))
        scene[f"copy{k}"] = {"type": "instance", "shapegroup": {"type": "ref", "id": "buddha"}, "to_world": to_world}
    t0 = time.perf_counter()
    loaded = mi.load_dict(scene)
    t1 = time.perf_counter()
    image = np.array(mi.render(loaded, spp=64))
    t2 = time.perf_counter()
    json.dump({"load": t1 - t0, "render": t2 - t1, "copies": k + 1, "mean": float(image.mean())}, open(out, "w"))


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "--mitsuba-child":
        return mitsuba_child(*sys.argv[2:])
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--count", type=int, default=10000, help="copies of the mesh (default 10000: a billion triangles)")
    ap.add_argument("--path-size", default="1024x768", help="the path frame's WxH (default 1024x768)")
    ap.add_argument("--vkrt", default=os.path.join(ROOT, "target/release/vkrt"))
    ap.add_argument("--mitsuba", metavar="PYTHON", help="an interpreter with PyPI mitsuba: adds its anchor row")
    args = ap.parse_args()
    if not os.path.exists(MESH):
        sys.exit(f"bench-billion: needs {MESH} (../shared)")
    width, height = args.path_size.split("x")
    frames = {
        "Whitted 1024x768": ["--width", "1024", "--height", "768"],
        f"path {args.path_size} 64 spp": ["--integrator", "path", "--spp", "64", "--width", width, "--height", height],
    }
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "scene.yaml")
        subprocess.run([sys.executable, os.path.join(ROOT, "tools/make_instanced_scene.py"), MESH, "--count", str(args.count), "--material", "-o", scene], check=True)
        results = {f: [] for f in frames}
        anchor = []
        for r in range(args.rounds):
            if args.mitsuba:
                out = os.path.join(tmp, "mitsuba.json")
                subprocess.run([args.mitsuba, os.path.abspath(__file__), "--mitsuba-child", scene, args.path_size, out], check=True)
                anchor.append(json.load(open(out)))
                print(f"round {r + 1} mitsuba: {anchor[-1]}", file=sys.stderr)
            for frame, extra in frames.items():
                results[frame].append(run(args.vkrt, scene, os.path.join(tmp, "out.pfm"), extra))
                print(f"round {r + 1} {frame}: {results[frame][-1]}", file=sys.stderr)
    keys = ["triangles", "load", "build", "upload", "prepare", "render", "bvh_mib", "shading_mib", "rss_gib"]
    print(f"| frame | {' | '.join(keys)} |")
    print("|---|" + "---|" * len(keys))
    for frame in frames:
        med = {k: statistics.median(x[k] for x in results[frame]) for k in keys}
        print(f"| {frame} | " + " | ".join(f"{int(med[k]):,}" if k == "triangles" else f"{med[k]:.4g}" for k in keys) + " |")
    if anchor:
        load = statistics.median(x["load"] for x in anchor)
        render = statistics.median(x["render"] for x in anchor)
        print(f"\nMitsuba 3 llvm_ad_rgb, {anchor[0]['copies']} instances, path {args.path_size} 64 spp, medians: load {load:.3g} s (its BVH build included), render {render:.3g} s (its JIT included)")


if __name__ == "__main__":
    main()
