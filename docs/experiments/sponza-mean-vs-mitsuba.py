#!/usr/bin/env python3
"""Whether vkrt's Sponza (the realistic ladder's scene, camera and map, 320x240) is darker than
Mitsuba 3's: N independent seeds of each at SPP (optionally both renderers at max depth DEPTH),
the sums over the dim pixels (the 2048-spp reference's luminance 0.01-0.05) and over all, over
the reference's; means, standard errors and the paired difference. Needs the reference
(tools/realistic_ladder.py --scenes sponza --reference-spp 2048), mitsuba and numpy:

    python3 docs/experiments/sponza-mean-vs-mitsuba.py 40 32 [DEPTH]

The vkrt binary is target/release/vkrt, or the one the VKRT variable names (a throwaway build).
"""
import sys, os, statistics, tempfile, numpy as np
import sponza_setup as sp
from path_time_to_error import mitsuba_scene
mi = sp.mi
WORK = tempfile.mkdtemp(prefix="vkrt-sponza-mean-")
mi.set_variant("llvm_ad_rgb")
N = int(sys.argv[1]); SPP = int(sys.argv[2]); DEPTH = int(sys.argv[3]) if len(sys.argv) > 3 else -1
ref, dim = sp.reference_and_dim()
print(f"dim pixels: {dim.sum()} of {dim.size}", flush=True)
scene = mitsuba_scene(mi, sp.OBJ, sp.MTL, sp.CAMERA, sp.WIDTH, sp.HEIGHT, WORK, sp.ENVMAP)
# None: the scene's own integrator (unbounded depth).
integ = mi.load_dict({"type": "path", "max_depth": DEPTH, "rr_depth": 5}) if DEPTH > 0 else None
depth_flags = ["--max-depth", str(DEPTH)] if DEPTH > 0 else []
VKRT = os.environ.get("VKRT", "target/release/vkrt")
res = {"vkrt": [], "mitsuba": []}
for k in range(N):
    seed = 100 + k
    v = sp.render_vkrt(VKRT, seed, SPP, os.path.join(WORK, "v.exr"), depth_flags)
    m = np.array(mi.render(scene, spp=SPP, seed=seed, integrator=integ), dtype=np.float64)[..., :3]
    for key, img in (("vkrt", v), ("mitsuba", m)):
        res[key].append((img[dim].sum() / ref[dim].sum(), img.sum() / ref.sum()))
    print(k, " ".join(f"{key} dim {res[key][-1][0]:.4f} all {res[key][-1][1]:.4f}" for key in res), flush=True)
for key in res:
    d = [x[0] for x in res[key]]; a = [x[1] for x in res[key]]
    print(f"{key}: dim {statistics.mean(d):.5f} +- {statistics.stdev(d)/len(d)**0.5:.5f}, all {statistics.mean(a):.5f} +- {statistics.stdev(a)/len(a)**0.5:.5f}")
dd = [x[0] - y[0] for x, y in zip(res["vkrt"], res["mitsuba"])]
print(f"vkrt - mitsuba dim: {statistics.mean(dd):+.5f} +- {statistics.stdev(dd)/len(dd)**0.5:.5f}")
