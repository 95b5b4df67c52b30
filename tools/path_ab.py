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
relMSE comes from `vkrt compare` and HDR-FLIP from path_time_to_error.py's `flip_hdr`, so the
numbers are those of the time-to-error benchmark; without flip-evaluator FLIP prints as "-".
"""
import argparse
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from path_time_to_error import flip_hdr, vkrt_compare  # noqa: E402


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
            found = re.search(r" in ([0-9.]+) s on ", res.stderr + res.stdout)
            if not found:
                sys.exit(f"{' '.join(cmd)}: no render time in its output")
            results[i].append((vkrt_compare(binary, out, args.reference), flip_hdr(out, args.reference), float(found.group(1))))
    for i, text in enumerate(args.configs):
        relmse = sum(r for r, _, _ in results[i]) / len(results[i])
        flips = [f for _, f, _ in results[i] if f is not None]
        flip_text = f"{sum(flips) / len(flips):.4f}" if flips else "-"
        times = [t for _, _, t in results[i]]
        print(f"{text:36s} relMSE {relmse:.4e} HDR-FLIP {flip_text} seconds {min(times):.2f} "
              f"(of {' '.join(f'{t:.2f}' for t in times)}) relMSE x s {relmse * min(times):.3e}")


if __name__ == "__main__":
    main()
