#!/usr/bin/env python3
"""Whether vkrt's Sponza (the realistic ladder's scene, camera and map, 320x240) is darker than
Mitsuba 3's: N independent seeds of each at SPP (optionally both renderers at max depth DEPTH),
the sums over the dim pixels (the 2048-spp reference's luminance 0.01-0.05) and over all, over
the reference's; means, standard errors and the paired difference. Needs the reference
(tools/realistic_ladder.py --scenes sponza --reference-spp 2048), mitsuba and numpy:

    python3 docs/experiments/sponza-mean-vs-mitsuba.py 40 32 [DEPTH]

The vkrt binary is target/release/vkrt, or the one the VKRT variable names (a throwaway build).
"""
import sys, os, subprocess, statistics, numpy as np
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools")); os.chdir(ROOT)
import realistic_ladder as rl
from types import SimpleNamespace
from path_time_to_error import vkrt_scene_flags, mitsuba_scene
import mitsuba as mi
import tempfile
WORK = tempfile.mkdtemp(prefix="vkrt-sponza-mean-")
mi.set_variant("llvm_ad_rgb")
N = int(sys.argv[1]); SPP = int(sys.argv[2]); DEPTH = int(sys.argv[3]) if len(sys.argv) > 3 else -1
name = "sponza"; spec = rl.SCENES[name]; obj, mtl, _, _ = rl.prepare(name, spec)
ref_path = rl.reference_path(name, spec, obj, mtl, 320, 240, 2048)
load = lambda p: np.array(mi.Bitmap(p).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32), dtype=np.float64)
ref = load(ref_path)
lum = ref @ np.array([0.2126, 0.7152, 0.0722])
dim = (lum >= 0.01) & (lum < 0.05)
print(f"dim pixels: {dim.sum()} of {dim.size}", flush=True)
cam = vkrt_scene_flags(SimpleNamespace(vkrt_camera=True, eye=spec["eye"], target=spec["target"], up=spec["up"], fov=spec["fov"], envmap=rl.ENVMAP))
scene = mitsuba_scene(mi, obj, mtl, {"eye": spec["eye"], "target": spec["target"], "up": spec["up"], "fov": spec["fov"]}, 320, 240, WORK, rl.ENVMAP)
# None: the scene's own integrator (unbounded depth).
integ = mi.load_dict({"type": "path", "max_depth": DEPTH, "rr_depth": 5}) if DEPTH > 0 else None
depth_flags = ["--max-depth", str(DEPTH)] if DEPTH > 0 else []
VKRT = os.environ.get("VKRT", "target/release/vkrt")
res = {"vkrt": [], "mitsuba": []}
for k in range(N):
    seed = 100 + k
    out = os.path.join(WORK, "v.exr")
    subprocess.run([VKRT, "render", obj, "--integrator", "path", "--width", "320", "--height", "240", "--spp", str(SPP),
                    "--seed", str(seed), "-o", out, *cam, *depth_flags], check=True, capture_output=True)
    v = load(out)
    m = np.array(mi.render(scene, spp=SPP, seed=seed, integrator=integ), dtype=np.float64)[..., :3]
    for key, img in (("vkrt", v), ("mitsuba", m)):
        res[key].append((img[dim].sum() / ref[dim].sum(), img.sum() / ref.sum()))
    print(k, " ".join(f"{key} dim {res[key][-1][0]:.4f} all {res[key][-1][1]:.4f}" for key in res), flush=True)
for key in res:
    d = [x[0] for x in res[key]]; a = [x[1] for x in res[key]]
    print(f"{key}: dim {statistics.mean(d):.5f} +- {statistics.stdev(d)/len(d)**0.5:.5f}, all {statistics.mean(a):.5f} +- {statistics.stdev(a)/len(a)**0.5:.5f}")
dd = [x[0] - y[0] for x, y in zip(res["vkrt"], res["mitsuba"])]
print(f"vkrt - mitsuba dim: {statistics.mean(dd):+.5f} +- {statistics.stdev(dd)/len(dd)**0.5:.5f}")
