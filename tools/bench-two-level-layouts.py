#!/usr/bin/env python3
"""The two-level BVH's levels in each layout (issue 44: threaded, multi-order, parent-link,
compact, wide): three instanced scenes written by tools/make_instanced_scene.py (copies turned about the vertical and
scaled, so that a copy's object-space axes are not the world's), each traced by `vkrt trace`
with camera rays (1024x768) and incoherent rays (1M) and rendered by the path tracer (320x240,
64 spp), the layouts in turn, ROUNDS rounds. Prints a Markdown table of medians:
traversal rays/s (device timestamps), nodes visited per ray, and path render seconds.

    python3 tools/bench-two-level-layouts.py [--rounds 3] [--vkrt target/release/vkrt] [--no-path]
        [--layouts threaded,multi-order,parent-link,compact,wide]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared", "scenes")
SCENES = [
    ("dragon x 100", "stanford-dragon-100k/dragon.obj", 100),
    ("bunny x 400", "stanford-bunny/bunny.obj", 400),
    ("buddha x 1000", "happy-buddha-100k/buddha.obj", 1000),
]
LAYOUTS = ["threaded", "multi-order", "parent-link", "compact", "wide"]


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, check=True).stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--vkrt", default=os.path.join(ROOT, "target/release/vkrt"))
    ap.add_argument("--no-path", action="store_true", help="leave out the path renders")
    ap.add_argument("--layouts", default=",".join(LAYOUTS), help="comma-separated layouts to compare")
    args = ap.parse_args()
    layouts = args.layouts.split(",")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, mesh, count in SCENES:
            mesh_path = os.path.join(SHARED, mesh)
            if not os.path.exists(mesh_path):
                sys.exit(f"bench-two-level-layouts: needs {mesh_path} (../shared)")
            scene = os.path.join(tmp, name.split()[0], "scene.yaml")
            subprocess.run([sys.executable, os.path.join(ROOT, "tools/make_instanced_scene.py"), mesh_path, "--count", str(count), "-o", scene], check=True, capture_output=True)
            rays = {
                "camera": ["--kind", "primary", "--width", "1024", "--height", "768"],
                "incoherent": ["--kind", "incoherent", "--count", "1000000"],
            }
            for kind, flags in rays.items():
                run([args.vkrt, "rays", scene, *flags, "-o", os.path.join(tmp, f"{kind}.npy")])
            got = {(kind, layout): [] for kind in list(rays) + ["path"] for layout in layouts}
            nodes = {}
            for _ in range(args.rounds):
                for kind in rays:
                    for layout in layouts:
                        text = run([args.vkrt, "trace", scene, "--rays", os.path.join(tmp, f"{kind}.npy"), "-o", os.path.join(tmp, "hits.npy"), "--layout", layout])
                        if f"two-level {layout}" not in text:
                            sys.exit(f"bench-two-level-layouts: {name} was not traced through the two-level BVH:\n{text}")
                        got[(kind, layout)].append(float(re.search(r"traversal alone ([\d.]+) M rays/s", text).group(1)))
                        nodes[(kind, layout)] = float(re.search(r"([\d.]+) nodes visited", text).group(1))
                if not args.no_path:
                    for layout in layouts:
                        out = os.path.join(tmp, "path.exr")
                        text = run([args.vkrt, "render", scene, "-o", out, "--width", "320", "--height", "240", "--spp", "64", "--layout", layout, "--cache", "off", "-v"])
                        got[("path", layout)].append(float(re.search(r"rendered .* in ([\d.]+) s", text).group(1)))
            rows.append((name, got, nodes))
    print(f"{args.rounds} rounds, medians; traversal M rays/s by device timestamps (nodes visited per ray); path 320x240 64 spp seconds\n")
    print("| scene | layout | camera | incoherent | path s |")
    print("|---|---|---:|---:|---:|")
    for name, got, nodes in rows:
        for layout in layouts:
            med = lambda k: statistics.median(got[(k, layout)]) if got[(k, layout)] else float("nan")
            cells = [f"{med(k):.2f} ({nodes[(k, layout)]:.1f})" for k in ("camera", "incoherent")]
            print(f"| {name} | {layout} | {cells[0]} | {cells[1]} | {med('path'):.2f} |")


if __name__ == "__main__":
    main()
