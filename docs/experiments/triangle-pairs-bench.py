#!/usr/bin/env python3
"""A/B of vkrt binaries (docs/experiments/triangle-pairs.md): `vkrt trace` M rays/s on camera and
incoherent rays (Conference, Sponza, Sibenik, the ladder's dragon) and path-tracer render seconds
on the five realistic ladder scenes at 320x240, binaries interleaved round by round (the order
reversed every other round), medians printed; then how often the first two binaries' hits agree.

    python3 tools/realistic_ladder.py --prepare-only
    MODE=trace,path LAYOUT=threaded SPP=16 python3 docs/experiments/triangle-pairs-bench.py ROUNDS NAME=BINARY NAME=BINARY...

Each binary gets its own VKRT_CACHE folder, so that no binary reads another's prepared scenes.
"""
import os, re, subprocess, sys, statistics, tempfile
from types import SimpleNamespace
import numpy as np
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from path_time_to_error import vkrt_scene_flags  # noqa: E402
import realistic_ladder as rl  # noqa: E402
TMP = tempfile.mkdtemp(prefix="vkrt-ab-")
bins = dict(a.split("=", 1) for a in sys.argv[2:])
rounds = int(sys.argv[1])
mode = os.environ.get("MODE", "trace,path").split(",")
S = os.path.join(ROOT, "..", "shared", "scenes")
R = os.path.join(ROOT, "target", "bench", "realistic")
trace_scenes = {"conference": f"{S}/conference/conference.obj", "sponza": f"{S}/sponza-dabrovic/sponza.obj",
                "sibenik": f"{S}/sibenik/sibenik.obj", "dragon": f"{R}/dragon/dragon.obj"}
gen = list(bins.values())[0]
os.makedirs(f"{TMP}/rays", exist_ok=True)
for name, obj in trace_scenes.items():
    for kind in ["primary", "incoherent"]:
        out = f"{TMP}/rays/{name}-{kind}.npy"
        if not os.path.exists(out):
            extra = ["--width", "1024", "--height", "1024"] if kind == "primary" else ["--count", str(1 << 20)]
            subprocess.run([gen, "rays", obj, "--kind", kind, "-o", out, *extra], check=True, capture_output=True)
# The ladder's scenes as its tool writes them, with their cameras and maps.
path_scenes = {name: (os.path.join(R, name, f"{name}.obj"),
                      vkrt_scene_flags(SimpleNamespace(vkrt_camera=True, eye=spec["eye"], target=spec["target"], up=spec["up"], fov=spec["fov"],
                                                       envmap=os.path.join(ROOT, rl.ENVMAP) if spec["envmap"] else None)))
               for name, spec in rl.SCENES.items()}
spp = os.environ.get("SPP", "16")
res = {}
for r in range(rounds):
    for b, path in (bins.items() if r % 2 == 0 else reversed(list(bins.items()))):
        if "trace" in mode:
            for name, obj in trace_scenes.items():
                for kind in ["primary", "incoherent"]:
                    p = subprocess.run([path, "trace", obj, "--rays", f"{TMP}/rays/{name}-{kind}.npy", "--out", f"{TMP}/{b}-{name}-{kind}.npy", "--layout", os.environ.get("LAYOUT", "threaded")],
                                       capture_output=True, text=True, env={**os.environ, "VKRT_CACHE": f"{TMP}/cache-{b}"})
                    m = re.search(r"([0-9.]+) M rays/s", p.stderr + p.stdout)
                    if not m: print(p.stderr); sys.exit(1)
                    res.setdefault((f"trace {name} {kind}", b), []).append(float(m.group(1)))
        if "path" in mode:
            for name, (obj, scene_flags) in path_scenes.items():
                cmd = [path, "render", obj, "-o", f"{TMP}/{b}-{name}.pfm", "--integrator", "path", "--width", "320", "--height", "240",
                       "--spp", spp, "-v", *scene_flags]
                p = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "VKRT_CACHE": f"{TMP}/cache-{b}"})
                m = re.search(r" in ([0-9.]+) s on ", p.stderr)
                if not m: print(p.stderr); sys.exit(1)
                res.setdefault((f"path {name} {spp}spp s", b), []).append(float(m.group(1)))
    print(f"round {r+1} done", file=sys.stderr, flush=True)
names = list(bins)
rows = list(dict.fromkeys(w for w, _ in res))
print("| workload | " + " | ".join(names) + " | ratio |")
print("|---|" + "---|" * (len(names) + 1))
for w in rows:
    meds = [statistics.median(res[(w, b)]) for b in names]
    cells = [" / ".join(f"{x:.3g}" for x in res[(w, b)]) + f" (med {m:.3g})" for b, m in zip(names, meds)]
    print(f"| {w} | " + " | ".join(cells) + f" | {meds[1]/meds[0]:.3f} |")
if "trace" in mode and len(names) == 2:
    for name in trace_scenes:
        for kind in ["primary", "incoherent"]:
            a = np.load(f"{TMP}/{names[0]}-{name}-{kind}.npy"); c = np.load(f"{TMP}/{names[1]}-{name}-{kind}.npy")
            ta, tc = a["t"], c["t"]
            differ = int(np.sum(~((ta == tc) | (np.isinf(ta) & np.isinf(tc)))))
            prims = int(np.sum(a["prim"] != c["prim"]))
            print(f"hits {name} {kind}: {differ} of {len(ta)} rays with another t, {prims} with another primitive")
