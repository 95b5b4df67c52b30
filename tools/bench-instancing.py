#!/usr/bin/env python3
"""The cost of the second level (issue 44): the 10M-triangle Buddha grid of
scenes/bench/buddha-grid-10m.yaml as 100 `Instances` of one mesh against the same grid as 100
`Models` (expanded), rendered by `vkrt render --cache off -v` alternately, ROUNDS rounds: a
1024x768 Whitted frame and a 320x240 64-spp path frame. Prints a Markdown table of medians:
load, BVH build, upload, render seconds, the device arrays' MiB (`render -v`) and the process's
peak resident memory. With --mitsuba PYTHON (an interpreter with PyPI mitsuba; Debian's
libllvm19 for llvm_ad_rgb), the anchor in the same rounds: Mitsuba 3 loading the same grid as a
`shapegroup` with 100 `instance`s and as 100 shapes, then its 320x240 64-spp path frame.

    python3 tools/bench-instancing.py [--rounds 3] [--vkrt target/release/vkrt] [--mitsuba PYTHON]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scenes(tmp):
    """The grid as Models (the repository's file, its mesh path made absolute) and as Instances."""
    src = open(os.path.join(ROOT, "scenes/bench/buddha-grid-10m.yaml")).read()
    mesh = os.path.normpath(os.path.join(ROOT, "scenes/bench", re.search(r"Mesh: (\S+)", src).group(1)))
    if not os.path.exists(mesh):
        sys.exit(f"bench-instancing: needs {mesh} (../shared)")
    shifts = re.findall(r"Translation: \[([^\]]*)\]", src)
    head = src[: src.index("Models:")]
    expanded = head + "Models:\n" + "".join(f"  - Mesh: {mesh}\n    Translation: [{t}]\n    Material: stone\n" for t in shifts)
    instanced = head + f"Instances:\n  - Mesh: {mesh}\n    Material: stone\n    Transforms:\n" + "".join(f"      - Translation: [{t}]\n" for t in shifts)
    paths = {}
    for name, text in [("expanded", expanded), ("instanced", instanced)]:
        paths[name] = os.path.join(tmp, f"{name}.yaml")
        open(paths[name], "w").write(text)
    return paths


def run(vkrt, scene, out, extra):
    cmd = ["/usr/bin/time", "-f", "maxrss %M", vkrt, "render", scene, "-o", out, "--cache", "off", "-v"] + extra
    text = subprocess.run(cmd, capture_output=True, text=True, check=True).stderr
    num = lambda pattern: float(re.search(pattern, text).group(1))
    return {
        "triangles": num(r": (\d+) triangles"),
        "load": num(r"load ([\d.]+) s"),
        "build": num(r"BVH build ([\d.]+) s"),
        "upload": num(r"upload ([\d.]+) s"),
        "render": num(r"rendered .* in ([\d.]+) s"),
        "bvh_mib": num(r"device arrays: BVH ([\d.]+) MiB"),
        "shading_mib": num(r"shading ([\d.]+) MiB"),
        "rss_gib": num(r"maxrss (\d+)") / 2**20,
    }


def mitsuba_child(form, mesh, out):
    """Runs in the Mitsuba interpreter: load the grid (`form`) and render it; prints JSON times."""
    import json
    import time
    import mitsuba as mi
    import numpy as np
    mi.set_variant("llvm_ad_rgb")
    src = open(os.path.join(ROOT, "scenes/bench/buddha-grid-10m.yaml")).read()
    shifts = [[float(v) for v in t.split(",")] for t in re.findall(r"Translation: \[([^\]]*)\]", src)]
    bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.6, 0.6, 0.6]}}
    scene = {
        "type": "scene",
        "integrator": {"type": "path"},
        "sensor": {
            "type": "perspective", "fov": 45, "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=[20, 30, 95], target=[20, 5, 22], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": 320, "height": 240},
        },
        "sun": {"type": "directional", "direction": [-1, -2, -1.5], "irradiance": {"type": "rgb", "value": [1, 1, 1]}},
    }
    if form == "instanced":
        scene["buddha"] = {"type": "shapegroup", "mesh": {"type": "obj", "filename": mesh, "bsdf": bsdf}}
        for k, t in enumerate(shifts):
            scene[f"copy{k}"] = {"type": "instance", "shapegroup": {"type": "ref", "id": "buddha"}, "to_world": mi.ScalarTransform4f().translate(t)}
    else:
        for k, t in enumerate(shifts):
            scene[f"copy{k}"] = {"type": "obj", "filename": mesh, "bsdf": bsdf, "to_world": mi.ScalarTransform4f().translate(t)}
    t0 = time.perf_counter()
    loaded = mi.load_dict(scene)
    t1 = time.perf_counter()
    image = np.array(mi.render(loaded, spp=64))
    t2 = time.perf_counter()
    json.dump({"load": t1 - t0, "render": t2 - t1, "mean": float(image.mean())}, open(out, "w"))


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "--mitsuba-child":
        return mitsuba_child(*sys.argv[2:])
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--vkrt", default=os.path.join(ROOT, "target/release/vkrt"))
    ap.add_argument("--mitsuba", metavar="PYTHON", help="an interpreter with PyPI mitsuba: adds its anchor rows")
    args = ap.parse_args()
    frames = {
        "Whitted 1024x768": ["--width", "1024", "--height", "768"],
        "path 320x240 64 spp": ["--integrator", "path", "--spp", "64", "--width", "320", "--height", "240"],
    }
    with tempfile.TemporaryDirectory() as tmp:
        paths = scenes(tmp)
        results = {(f, s): [] for f in frames for s in paths}
        mesh = re.search(r"Mesh: (\S+)", open(paths["instanced"]).read()).group(1)
        anchor = {form: [] for form in paths}
        for r in range(args.rounds):
            if args.mitsuba:
                for form in (["expanded", "instanced"] if r % 2 == 0 else ["instanced", "expanded"]):
                    out = os.path.join(tmp, "mitsuba.json")
                    subprocess.run([args.mitsuba, os.path.abspath(__file__), "--mitsuba-child", form, mesh, out], check=True)
                    anchor[form].append(__import__("json").load(open(out)))
                    print(f"round {r + 1} mitsuba {form}: {anchor[form][-1]}", file=sys.stderr)
            for frame, extra in frames.items():
                # Alternate which form goes first, so that neither always runs on a warmer machine.
                order = ["expanded", "instanced"] if r % 2 == 0 else ["instanced", "expanded"]
                for form in order:
                    results[(frame, form)].append(run(args.vkrt, paths[form], os.path.join(tmp, f"{form}.pfm"), extra))
                    print(f"round {r + 1} {frame} {form}: {results[(frame, form)][-1]}", file=sys.stderr)
    keys = ["load", "build", "upload", "render", "bvh_mib", "shading_mib", "rss_gib"]
    print(f"| frame | form | {' | '.join(keys)} |")
    print("|---|---|" + "---|" * len(keys))
    for frame in frames:
        med = {form: {k: statistics.median(x[k] for x in results[(frame, form)]) for k in keys} for form in paths}
        for form in ["expanded", "instanced"]:
            print(f"| {frame} | {form} | " + " | ".join(f"{med[form][k]:.3g}" for k in keys) + " |")
        print(f"| {frame} | instanced / expanded | " + " | ".join(f"{med['instanced'][k] / med['expanded'][k]:.3f}x" for k in keys) + " |")
    if args.mitsuba:
        print("\nMitsuba 3 llvm_ad_rgb, path 320x240 64 spp, medians (load includes its BVH build, render its JIT):\n")
        print("| form | load | render | load + render |\n|---|---|---|---|")
        for form in ["expanded", "instanced"]:
            load = statistics.median(x["load"] for x in anchor[form])
            render = statistics.median(x["render"] for x in anchor[form])
            both = statistics.median(x["load"] + x["render"] for x in anchor[form])
            print(f"| {form} | {load:.3g} | {render:.3g} | {both:.3g} |")


if __name__ == "__main__":
    main()
