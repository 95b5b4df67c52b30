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
import numpy as np
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
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
env = os.path.join(ROOT, "tests", "refs", "envmap-sun.exr")
path_scenes = {
    "sponza": (f"{R}/sponza/sponza.obj", "13.5,1.8,-0.6", "-12.0,5.5,0.6", 60, True),
    "sibenik": (f"{R}/sibenik/sibenik.obj", "-17.0,-11.5,0.0", "10.0,-8.0,0.0", 60, False),
    "conference": (f"{R}/conference/conference.obj", "1500.0,330.0,-210.0", "-900.0,180.0,-210.0", 60, False),
    "dragon": (f"{R}/dragon/dragon.obj", "9.0,9.0,20.0", "0.0,4.0,0.0", 40, True),
    "buddha": (f"{R}/buddha/buddha.obj", "6.0,7.0,16.0", "0.0,4.8,0.0", 40, True),
}
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
            for name, (obj, eye, tgt, fov, envmap) in path_scenes.items():
                cmd = [path, "render", obj, "-o", f"{TMP}/{b}-{name}.pfm", "--integrator", "path", "--width", "320", "--height", "240",
                       "--spp", spp, f"--eye={eye}", f"--target={tgt}", "--up=0,1,0", f"--fov={fov}", "-v"] + (["--envmap", env] if envmap else [])
                p = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "VKRT_CACHE": f"{TMP}/cache-{b}"})
                m = re.search(r" in ([0-9.]+) s on ", p.stderr)
                if not m: print(p.stderr); sys.exit(1)
                res.setdefault((f"path {name} {spp}spp s", b), []).append(float(m.group(1)))
    print(f"round {r+1} done", file=sys.stderr, flush=True)
names = list(bins)
rows = sorted({k for k, _ in res}, key=lambda k: list(dict.fromkeys(k for k, _ in res)).index(k))
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
