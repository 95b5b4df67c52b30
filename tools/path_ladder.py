#!/usr/bin/env python3
"""Issue 17's benchmark in one command: the 16 / 64 / 256 spp ladder of the path tracer against
Mitsuba 3 on its three Cornell boxes (cornell-measured 512², CornellBox-Mirror and
CornellBox-Sphere 256²), each run by tools/path_time_to_error.py with --rounds 2 (shortest of two
interleaved rounds), then one summary: per scene and sample count, relMSE x seconds of vkrt over
Mitsuba's (the goal: <= 0.5x) and HDR-FLIP at equal time (Mitsuba's FLIP log-log interpolated at
vkrt's time along the bracketing segment of its curve, extrapolated along the end segment past
its ends; none with a single sample count; the goal: lower), with the machine named.

References: cornell-measured uses ../shared/refs/cornell-512.exr; the Mirror and Sphere boxes
use Mitsuba renders that this tool makes first where absent (`--make-reference`, 8192 spp, in
target/bench/refs: some minutes each). `--clean-references` makes and uses cleaner ones for all
three (cornell-measured 8192 spp, the Sphere box 32768): at 256 spp vkrt's error is a few times a
reference's own noise, which a noisy reference adds to both renderers' relMSE alike and so
pushes the ratio towards 1.

A benchmark, not a test: its numbers compare only inside one run on one machine (BENCHMARKS.md).

Usage (after `cargo build --release`; needs PyPI mitsuba, numpy and flip-evaluator, and libLLVM
19 for Mitsuba's llvm_ad_rgb: Debian 12 `libllvm19`):
  python3 tools/path_ladder.py [--out target/bench/ladder] [--clean-references] [--spp 16 64 256]
"""
import argparse
import csv
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BOXES = "../shared/scenes/cornell-box"


def box(name, eye_y, eye_z):
    """The flags of a bare Cornell-box OBJ with its own camera (as `vkrt render -v` prints it)."""
    obj = f"{BOXES}/{name}.obj"
    return ["--scene", obj, "--obj", obj, "--mtl", f"{BOXES}/{name}.mtl",
            "--eye", "-0.00999999", eye_y, eye_z, "--target", "-0.00999999", eye_y, "-0.024999976",
            "--fov", "45", "--width", "256", "--height", "256"]


# (name, flags, default reference and its spp (None: given), clean reference and its spp)
SCENES = [
    ("cornell", ["--scene", "scenes/cornell-measured/cornell.yaml"],
     ("../shared/refs/cornell-512.exr", None), ("target/bench/refs/cornell-512-8192.exr", 8192)),
    ("mirror", box("CornellBox-Mirror", "0.995", "4.5314026"),
     ("target/bench/refs/mirror-256.exr", 8192), ("target/bench/refs/mirror-256.exr", 8192)),
    ("sphere", box("CornellBox-Sphere", "0.795", "4.2547464"),
     ("target/bench/refs/sphere-256.exr", 8192), ("target/bench/refs/sphere-256-32768.exr", 32768)),
]


def tool(args):
    cmd = [sys.executable, os.path.join(HERE, "path_time_to_error.py"), *args]
    print("+", " ".join(cmd), flush=True)
    if subprocess.run(cmd, cwd=ROOT).returncode != 0:
        sys.exit(f"path_time_to_error.py failed: {' '.join(args)}")


def loglog(points, t):
    """FLIP at time t on the log-log polyline through (seconds, FLIP) `points` (its end segments
    extended past the ends), or None with fewer than two points: one point says nothing about
    FLIP at another time, and reporting it as "at vkrt's time" would compare unequal times."""
    points = sorted(points)
    if len(points) < 2:
        return None
    for i in range(len(points) - 1):
        if t <= points[i + 1][0] or i == len(points) - 2:
            (t0, f0), (t1, f1) = points[i], points[i + 1]
            a = (math.log(f1) - math.log(f0)) / (math.log(t1) - math.log(t0))
            return math.exp(math.log(f0) + a * (math.log(t) - math.log(t0)))


def summary(name, csv_path):
    """Rows of (scene, spp, ratio, vkrt FLIP, Mitsuba's FLIP at vkrt's time) from the tool's CSV."""
    rows = list(csv.DictReader(open(csv_path)))
    vkrt = {int(r["spp"]): r for r in rows if r["renderer"].startswith("vkrt")}
    mitsuba = {int(r["spp"]): r for r in rows if r["renderer"].startswith("mitsuba")}
    curve = [(float(r["seconds"]), float(r["flip_hdr"])) for r in mitsuba.values() if r["flip_hdr"]]
    out = []
    for spp in sorted(vkrt):
        if spp not in mitsuba:
            continue
        v, m = vkrt[spp], mitsuba[spp]
        ratio = float(v["relmse_x_seconds"]) / float(m["relmse_x_seconds"])
        flip = float(v["flip_hdr"]) if v["flip_hdr"] else None
        at = loglog(curve, float(v["seconds"])) if curve and flip is not None else None
        out.append((name, spp, ratio, flip, at))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="target/bench/ladder")
    ap.add_argument("--spp", nargs="+", default=["16", "64", "256"])
    ap.add_argument("--clean-references", action="store_true", help="make and use the cleaner references (cornell 8192 spp, Sphere 32768)")
    ap.add_argument("--vkrt", default="target/release/vkrt")
    args = ap.parse_args()
    os.chdir(ROOT)
    results = []
    for name, flags, default_ref, clean_ref in SCENES:
        ref, ref_spp = clean_ref if args.clean_references else default_ref
        if not os.path.exists(ref):
            if ref_spp is None:
                sys.exit(f"{name}: reference {ref} is missing (../shared/refs must be beside the repository)")
            os.makedirs(os.path.dirname(ref), exist_ok=True)
            tool([*flags, "--reference", ref, "--make-reference", str(ref_spp)])
        out = os.path.join(args.out, name)
        tool([*flags, "--reference", ref, "--spp", *args.spp, "--samplers", "zsobol", "--rounds", "2", "--vkrt", args.vkrt, "--out", out])
        results += summary(name, os.path.join(out, "time_to_error.csv"))
    print("\n| scene | spp | relMSE x s, vkrt / Mitsuba | HDR-FLIP vkrt | Mitsuba's at vkrt's time | FLIP at equal time |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, spp, ratio, flip, at in results:
        f = lambda x: f"{x:.4f}" if x is not None else "-"
        diff = f"{(flip / at - 1) * 100:+.0f} %" if flip is not None and at else "-"
        print(f"| {name} | {spp} | {ratio:.3f}x | {f(flip)} | {f(at)} | {diff} |")
    worst = max(r[2] for r in results) if results else float("nan")
    print(f"\nworst relMSE x s ratio {worst:.3f}x (goal <= 0.5x); the machine is named above each scene's table")


if __name__ == "__main__":
    main()
