"""Path tracer render time by BVH layout on the realistic ladder's scenes (issue 46): the same
scene, camera, size and samples, layouts alternating per round; render seconds as vkrt prints
them ("rendered ... in S s": load and prepare excluded), medians; image bytes compared."""
import os, re, statistics, subprocess, sys, hashlib
sys.path.insert(0, "tools")  # run from the repository root
from realistic_ladder import SCENES, PREPARED, ENVMAP

VKRT = "target/release/vkrt"
layouts = sys.argv[1].split(",") if len(sys.argv) > 1 else ["threaded", "multi-order", "compact"]
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
spp = sys.argv[3] if len(sys.argv) > 3 else "64"
names = sys.argv[4].split(",") if len(sys.argv) > 4 else list(SCENES)
v = lambda t: ",".join(f"{x:g}" for x in t)
for name in names:
    s = SCENES[name]
    obj = os.path.join(PREPARED, name, f"{name}.obj")
    base = [VKRT, "render", obj, "--integrator", "path", "--spp", spp, "--width", "320", "--height", "240",
            "--eye", v(s["eye"]), "--target", v(s["target"]), "--up", v(s["up"]), "--fov", f"{s['fov']:g}"]
    if s["envmap"]:
        base += ["--envmap", ENVMAP]
    times = {l: [] for l in layouts}
    digests = {}
    for r in range(rounds + 1):
        for l in layouts:
            out = f"target/bench/layouts-{name}-{l}.pfm"
            e = subprocess.run(base + ["--layout", l, "-o", out], capture_output=True, text=True)
            if e.returncode:
                sys.exit(e.stderr)
            t = float(re.search(r" in ([0-9.]+) s on", e.stderr).group(1))
            if r > 0:
                times[l].append(t)
            digests[l] = hashlib.sha1(open(out, "rb").read()).hexdigest()[:10]
    ref = statistics.median(times[layouts[0]])
    print(f"{name:>10}: " + ", ".join(f"{l} {statistics.median(times[l]):.3f} s ({statistics.median(times[l]) / ref:.3f}x)" for l in layouts)
          + ("; same bytes" if len(set(digests.values())) == 1 else f"; DIFFERENT bytes {digests}"), flush=True)
