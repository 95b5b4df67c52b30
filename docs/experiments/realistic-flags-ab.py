#!/usr/bin/env python3
"""A/B of vkrt render flags on the realistic ladder's scenes (tools/realistic_ladder.py: its
scenes, cameras and maps, 320x240): each configuration "SPP FLAGS..." renders with seeds 1..N,
interleaved; prints the mean relMSE and HDR-FLIP against the scene's Mitsuba reference of
REF_SPP samples (made first with tools/realistic_ladder.py, or by this repository's
tools/path_time_to_error.py --make-reference as the ladder calls it), the median render time
and relMSE x that time. Run from anywhere after `cargo build --release`:

    python3 docs/experiments/realistic-flags-ab.py REF_SPP SEEDS sibenik,conference "64 --connections auto" "64 --connections off"
"""
import sys, os, re, subprocess, statistics
from types import SimpleNamespace
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from path_time_to_error import flip_hdr, vkrt_compare, vkrt_scene_flags  # noqa: E402
import realistic_ladder as rl  # noqa: E402
os.chdir(ROOT)
binary = "target/release/vkrt"
TMP = __import__("tempfile").mkdtemp(prefix="vkrt-flags-ab-")
ref_spp = int(sys.argv[1]); seeds = int(sys.argv[2]); scenes = sys.argv[3].split(","); configs = sys.argv[4:]
for name in scenes:
    spec = rl.SCENES[name]
    obj, mtl, _, _ = rl.prepare(name, spec)
    ref = rl.reference_path(name, spec, obj, mtl, 320, 240, ref_spp)
    if not os.path.exists(ref):
        sys.exit(f"no reference {ref}: make it first (tools/realistic_ladder.py --scenes {name} --reference-spp {ref_spp})")
    cam = vkrt_scene_flags(SimpleNamespace(vkrt_camera=True, eye=spec["eye"], target=spec["target"], up=spec["up"], fov=spec["fov"],
                                           envmap=rl.ENVMAP if spec["envmap"] else None))
    res = {c: [] for c in configs}
    for seed in range(1, seeds + 1):
        for c in configs:
            spp, *extra = c.split()
            out = f"{TMP}/{name}-{configs.index(c)}-{seed}.exr"
            cmd = [binary, "render", obj, "--integrator", "path", "--width", "320", "--height", "240", "--spp", spp, "--seed", str(seed), "-o", out, *cam, *extra]
            p = subprocess.run(cmd, capture_output=True, text=True)
            m = re.search(r" in ([0-9.]+) s on ", p.stderr + p.stdout)
            if not m: sys.exit(p.stderr)
            res[c].append((vkrt_compare(binary, out, ref), flip_hdr(out, ref), float(m.group(1))))
    for c in configs:
        r = statistics.mean(x[0] for x in res[c]); f = statistics.mean(x[1] for x in res[c]); t = statistics.median(x[2] for x in res[c])
        print(f"{name:10s} {c:28s} relMSE {r:.4e} FLIP {f:.4f} s {t:.2f} ({' '.join(f'{x[2]:.2f}' for x in res[c])}) relMSE x s {r*t:.4e}", flush=True)
