#!/usr/bin/env python3
"""A/B of path-tracer configurations on one scene: each configuration renders with seeds 1-3
(interleaved: seed 1 of every configuration, then seed 2, ...), and the tool prints per
configuration the mean relMSE against a reference (mean((a-b)^2/(b^2+0.01)), as
../shared/refs/README.md defines it), the mean HDR-FLIP (`flip-evaluator` from PyPI), the
shortest render time of the three (the render's own "in N s", which excludes start-up) and
relMSE x that time. A benchmark for experiments, not a test; compare numbers from one run only.

Each configuration is `SPP` or `SPP|EXTRA ARGS` or `BINARY|SPP|EXTRA ARGS`, e.g.

    python3 tools/path_ab.py --scene ../shared/scenes/cornell-box/CornellBox-Mirror.obj \\
        --reference target/bench/refs/mirror-256.exr --size 256 \\
        "64|--coherence-block 16" "80|--coherence-block 8"

(the Mirror and Sphere references come from tools/path_time_to_error.py --make-reference).
Reads EXR through mitsuba's Bitmap, as path_time_to_error.py does.
"""
import argparse
import re
import subprocess
import sys

import numpy as np


def parse_config(text, default_binary):
    parts = text.split("|")
    if len(parts) == 1:
        return default_binary, parts[0], []
    if len(parts) == 2:
        return default_binary, parts[0], parts[1].split()
    if len(parts) == 3:
        return parts[0], parts[1], parts[2].split()
    sys.exit(f"configuration '{text}': expected SPP, SPP|ARGS or BINARY|SPP|ARGS")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", required=True, help="scene file vkrt renders")
    ap.add_argument("--reference", required=True, help="reference image (.exr) of the same camera and size")
    ap.add_argument("--size", type=int, default=256, help="image width and height in pixels (default 256)")
    ap.add_argument("--binary", default="target/release/vkrt", help="vkrt binary for configurations that name none")
    ap.add_argument("--seeds", type=int, default=3, help="seeds 1..N per configuration (default 3)")
    ap.add_argument("--out", default="/tmp", help="folder for the rendered images (default /tmp)")
    ap.add_argument("configs", nargs="+", help="configurations: SPP, SPP|ARGS or BINARY|SPP|ARGS")
    args = ap.parse_args()
    try:
        import flip_evaluator as flip
        import mitsuba as mi
    except ImportError as e:
        sys.exit(f"needs mitsuba and flip-evaluator (pip install mitsuba flip-evaluator): {e}")
    mi.set_variant("scalar_rgb")

    def load(path):
        return np.array(mi.Bitmap(path), dtype=np.float32)[..., :3]

    ref = load(args.reference)
    configs = [parse_config(c, args.binary) for c in args.configs]
    results = {i: [] for i in range(len(configs))}
    for seed in range(1, args.seeds + 1):
        for i, (binary, spp, extra) in enumerate(configs):
            out = f"{args.out}/path_ab-{i}-{seed}.exr"
            cmd = [binary, "render", args.scene, "--integrator", "path", "--width", str(args.size), "--height",
                   str(args.size), "--spp", spp, "--seed", str(seed), "-o", out] + extra
            res = subprocess.run(cmd, capture_output=True, text=True)
            if res.returncode != 0:
                sys.exit(f"{' '.join(cmd)} failed:\n{res.stderr}")
            found = re.search(r"in ([0-9.]+) s", res.stderr + res.stdout)
            if not found:
                sys.exit(f"{' '.join(cmd)}: no render time in its output")
            image = load(out)
            if image.shape != ref.shape:
                sys.exit(f"{out} is {image.shape}, the reference {ref.shape}")
            relmse = float((((image - ref) ** 2) / (ref ** 2 + 0.01)).mean())
            _, flip_mean, _ = flip.evaluate(ref, image, "HDR")
            results[i].append((relmse, float(flip_mean), float(found.group(1))))
    for i, text in enumerate(args.configs):
        v = np.array(results[i])
        times = " ".join(f"{t:.2f}" for t in v[:, 2])
        print(f"{text:36s} relMSE {v[:, 0].mean():.4e} HDR-FLIP {v[:, 1].mean():.4f} "
              f"seconds {v[:, 2].min():.2f} (of {times}) relMSE x s {v[:, 0].mean() * v[:, 2].min():.3e}")


if __name__ == "__main__":
    main()
