#!/usr/bin/env python3
"""Time-vs-error benchmark of the path tracer (and Mitsuba 3 when installed), side by side.

For a scene and an independent reference image, renders at a ladder of sample counts, records
the render time and the relMSE against the reference (mean((a-b)^2/(b^2+0.01)), as
../shared/refs/README.md defines it), writes a CSV and a log-log plot of error against seconds
(if matplotlib is installed), and prints relMSE x seconds, the figure of merit: for an unbiased
renderer relMSE falls as 1/time, so the product is constant and smaller is faster.

Times are render times: vkrt's own report ("in X s": BVH build and upload excluded, pipeline
creation and read-back included; each round line says how much was pipeline creation) and
Mitsuba's mi.render(). Each renderer first makes one warm-up render that is not counted:
Mitsuba's JIT compiles its kernels, vkrt fills its shader cache (and Mesa's) as any earlier run
on the machine would, so that a first round on a fresh machine does not time a shader compile
(its pipeline creation from the cache, ~0.01 s, stays counted);
with --rounds N every row runs N times, interleaved, and keeps its shortest time. Each sample
count runs every vkrt configuration and then Mitsuba back to back.

Usage (from the repository root, after `cargo build --release`):
  tools/path_time_to_error.py --scene scenes/cornell-measured/cornell.yaml \
      --reference ../shared/refs/cornell-512.exr --spp 1 4 16 64 --out target/bench/path
The two other Cornell boxes of issue 17, with a Mitsuba reference made by the tool first
(`--make-reference SPP` renders only that; the bare OBJ's camera, as `vkrt render -v` prints it):
  tools/path_time_to_error.py --scene ../shared/scenes/cornell-box/CornellBox-Mirror.obj \
      --obj ../shared/scenes/cornell-box/CornellBox-Mirror.obj --mtl ../shared/scenes/cornell-box/CornellBox-Mirror.mtl \
      --eye -0.01 0.995 4.5314026 --target -0.01 0.995 -0.025 --fov 45 --width 256 --height 256 \
      --reference target/bench/refs/mirror-256.exr --make-reference 8192
  (then the same without --make-reference, with --spp ...; CornellBox-Sphere: eye -0.01 0.795 4.2547464,
  target -0.01 0.795 -0.025). Materials map onto Mitsuba's as `mitsuba_bsdf` says.
Scenes whose camera is not the scene file's own: `--vkrt-camera` gives vkrt --eye, --target,
--up and --fov as well; `--envmap FILE` lights both renderers with that map too (vkrt's
--envmap, Mitsuba's `envmap` emitter with the identity transform: the same convention).
tools/realistic_ladder.py runs it so on Sponza, Sibenik, Conference, the dragon and the Buddha.
Only the Python standard library is needed; matplotlib adds the plot, mitsuba adds its curve
(PyPI `mitsuba` and `numpy`, variant llvm_ad_rgb, needs libLLVM 19: Debian 12 `libllvm19`), and
`flip-evaluator` (PyPI; with mitsuba, whose EXR reader it uses) adds the perceptual metric: mean HDR-FLIP against the reference, for
every image of both renderers. relMSE alone rewards correlated samples (streaks, blocks), so a
change is a win only if both fall. The first lines printed (and OUT/machine.txt) name the
machine the numbers come from: CPU model, AVX-512 or not, the Vulkan driver with its Mesa and
LLVM versions, and Mitsuba's version.
"""

import argparse
import csv
import os
import re
import subprocess
import sys
import time


def coherence_flags(coherence):
    """vkrt's flags for a --coherence value of this tool: "default" (none: vkrt's defaults),
    "N" (N pixels in a row; 1 is none shared) or "N/B" (N pixels scattered over B x B blocks)."""
    if coherence == "default":
        return []
    n, _, block = coherence.partition("/")
    return ["--coherence", n, "--coherence-block", block or "0"] if n != "1" else ["--coherence", "1"]


def coherence_name(coherence):
    if coherence == "default":
        return "defaults"
    n, _, block = coherence.partition("/")
    return "coherence 1" if n == "1" else f"coherence {n} " + (f"scattered {block}" if block else "in rows")


def vkrt_render(binary, scene, out, width, height, spp, sampler, seed, coherence, adaptive=False, extra=()):
    """(seconds, pipeline-creation seconds or None) of one vkrt render; `extra`: more flags
    (vkrt_scene_flags: the camera and environment map, where given)."""
    cmd = [binary, "render", scene, "-o", out, "--integrator", "path", "--width", str(width),
           "--height", str(height), "--spp", str(spp), "--sampler", sampler, "--seed", str(seed), "-v"] \
        + coherence_flags(coherence) + (["--adaptive"] if adaptive else []) + list(extra)
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"vkrt failed: {' '.join(cmd)}\n{res.stderr}")
    m = re.search(r" in ([0-9.]+) s on ", res.stderr)
    if not m:
        sys.exit(f"no render time in vkrt's report:\n{res.stderr}")
    # The share of that time spent creating the pipeline (older binaries do not say).
    p = re.search(r"pipeline creation ([0-9.]+) s", res.stderr)
    return float(m.group(1)), float(p.group(1)) if p else None


def vkrt_scene_flags(args):
    """vkrt's flags for what this tool gives both renderers: the camera with --vkrt-camera
    (otherwise vkrt uses its scene's own, which --eye etc. must then match) and --envmap."""
    flags = []
    if args.vkrt_camera:
        vec = lambda v: ",".join(repr(float(x)) for x in v)
        # `--eye=-1,2,3`: a value that starts with "-" must be attached to its flag.
        flags += [f"--eye={vec(args.eye)}", f"--target={vec(args.target)}", f"--up={vec(args.up)}", f"--fov={float(args.fov)!r}"]
    if args.envmap:
        flags += ["--envmap", args.envmap]
    return flags


def flip_hdr(image, reference):
    """Mean HDR-FLIP of `image` against `reference` (file paths), or None without flip-evaluator.
    The images are read with Mitsuba's EXR reader (flip-evaluator's own segfaults on vkrt's
    EXR files), in a process of its own (beside the JIT-compiled llvm_ad_rgb variant it crashed)."""
    import importlib.util
    if importlib.util.find_spec("flip_evaluator") is None or importlib.util.find_spec("mitsuba") is None:
        return None
    code = ("import sys, numpy as np, flip_evaluator as f, mitsuba as mi; mi.set_variant('scalar_rgb'); "
            "load = lambda p: np.ascontiguousarray(np.array(mi.Bitmap(p).convert(mi.Bitmap.PixelFormat.RGB, "
            "mi.Struct.Type.Float32), dtype=np.float32)); "
            "print(f.evaluate(load(sys.argv[2]), load(sys.argv[1]), 'HDR', applyMagma=False)[1])")
    res = subprocess.run([sys.executable, "-c", code, image, reference], capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"flip-evaluator failed on {image}:\n{res.stderr}")
    return float(res.stdout.strip().splitlines()[-1])


def machine(binary, mitsuba_version):
    """One line naming where the numbers come from."""
    cpu, avx512 = "unknown CPU", False
    try:
        with open("/proc/cpuinfo") as f:
            text = f.read()
        m = re.search(r"^model name\s*:\s*(.+)$", text, re.M)
        cpu = m.group(1).strip() if m else cpu
        avx512 = bool(re.search(r"^flags\s*:.*\bavx512f\b", text, re.M))
        cores = len(re.findall(r"^processor\s*:", text, re.M))
    except OSError:
        cores = os.cpu_count()
    # `vkrt info`'s first device: its name, then the Vulkan and driver line (Mesa, LLVM).
    info = subprocess.run([binary, "info"], capture_output=True, text=True).stdout.splitlines()
    device = ", ".join(l.strip() for l in info[:2]) or "?"
    return (f"CPU: {cpu}, {cores} cores, AVX-512 {'yes' if avx512 else 'no'}; vkrt device: {device}; "
            f"Mitsuba: {mitsuba_version or 'not run'}")


def vkrt_compare(binary, image, reference):
    res = subprocess.run([binary, "compare", image, reference], capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"vkrt compare failed:\n{res.stderr}")
    m = re.search(r"^relmse\s+([0-9.eE+-]+)", res.stdout, re.M)
    if not m:
        sys.exit(f"no relmse in:\n{res.stdout}")
    return float(m.group(1))


def split_obj_by_material(obj_path, out_dir):
    """Mitsuba's OBJ loader ignores materials: write one OBJ per `usemtl` group. Returns
    {material: (path, has_normals)}: vertex normals are kept where the faces give them (vkrt
    shades with them), and parts without them get face normals."""
    verts, normals, groups, current = [], [], {}, None
    # Negative indices count back from the last vertex (or normal) so far: make them absolute.
    absolute = lambda i, n: i if i > 0 else n + 1 + i
    with open(obj_path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append(line)
            elif parts[0] == "vn":
                normals.append(line)
            elif parts[0] == "usemtl":
                current = parts[1]
            elif parts[0] == "f":
                face = []
                for p in parts[1:]:
                    idx = p.split("/")
                    vn = absolute(int(idx[2]), len(normals)) if len(idx) > 2 and idx[2] else None
                    face.append((absolute(int(idx[0]), len(verts)), vn))
                groups.setdefault(current, []).append(face)
    files = {}
    for name, faces in groups.items():
        path = os.path.join(out_dir, f"part-{name}.obj")
        with_normals = all(n is not None for face in faces for _, n in face)
        with open(path, "w") as f:
            f.writelines(verts)
            if with_normals:
                f.writelines(normals)
            corner = (lambda c: f"{c[0]}//{c[1]}") if with_normals else (lambda c: f"{c[0]}")
            for face in faces:
                # Fan-triangulate in file order, as vkrt does.
                for k in range(1, len(face) - 1):
                    f.write(f"f {corner(face[0])} {corner(face[k])} {corner(face[k + 1])}\n")
        files[name] = (path, with_normals)
    return files


def read_mtl(mtl_path):
    mats, cur = {}, None
    with open(mtl_path) as f:
        for line in f:
            p = line.split("#")[0].split()
            if not p:
                continue
            if p[0] == "newmtl":
                cur = mats.setdefault(p[1], {})
            elif cur is not None and p[0] in ("Kd", "Ke", "Ks"):
                cur[p[0]] = [float(x) for x in p[1:4]]
            elif cur is not None and p[0] in ("Ns", "Ni", "illum"):
                cur[p[0]] = float(p[1])
    return mats


def mitsuba_bsdf(m):
    """Mitsuba's BSDF for one MTL material, as vkrt reads it (shaders/include/bsdf.glsl,
    scene::Material): illum 4/6/7/9 a smooth untinted dielectric of index Ni; otherwise Lambert
    Kd (1 - max Ks) plus, where Ks > 0, a specular lobe Ks with no Fresnel term: a perfect mirror
    for illum 3/5, else GGX with alpha = sqrt(2 / (Ns + 2)) sampled by visible normals. Mitsuba
    has no such sum, so it is a `blendbsdf` of weight w = max Ks between a diffuse of reflectance
    Kd and a conductor of material "none" (reflectance 1, no Fresnel) scaled by Ks / w. Mitsuba's
    rough conductor shadows with separable Smith G, vkrt with height-correlated G: the two
    differ by well under 1 % at the Cornell boxes' alphas (0.045, 0.1). Missing fields take
    vkrt's defaults (Kd 0.8, Ks 0, Ns 0, Ni 1, illum 2)."""
    kd = m.get("Kd", [0.8] * 3)
    ks = [min(max(v, 0.0), 1.0) for v in m.get("Ks", [0.0] * 3)]
    illum = int(m.get("illum", 2))
    if illum in (4, 6, 7, 9):
        return {"type": "dielectric", "int_ior": m.get("Ni", 1.0), "ext_ior": 1.0}
    diffuse = {"type": "diffuse", "reflectance": {"type": "rgb", "value": kd}}
    w = max(ks)
    if w <= 0.0:
        return {"type": "twosided", "bsdf": diffuse}
    rgb = {"type": "rgb", "value": [v / w for v in ks]}
    if illum in (3, 5):
        spec = {"type": "conductor", "material": "none", "specular_reflectance": rgb}
    else:
        alpha = min(max((2.0 / (max(m.get("Ns", 0.0), 0.0) + 2.0)) ** 0.5, 1e-3), 1.0)
        spec = {"type": "roughconductor", "material": "none", "distribution": "ggx", "alpha": alpha,
                "sample_visible": True, "specular_reflectance": rgb}
    bsdf = spec if w >= 1.0 else {"type": "blendbsdf", "weight": w, "bsdf_0": diffuse, "bsdf_1": spec}
    return {"type": "twosided", "bsdf": bsdf}


def mitsuba_scene(mi, obj, mtl, camera, width, height, work, envmap=None):
    """Mitsuba's scene: the OBJ's parts with their MTL materials (area emitters where Ke > 0),
    and with `envmap` an `envmap` emitter of that file, identity transform (vkrt's --envmap
    follows Mitsuba's lat-long convention)."""
    parts = split_obj_by_material(obj, work)
    mats = read_mtl(mtl)
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1, "rr_depth": 5},
        "sensor": {
            "type": "perspective", "fov": camera["fov"], "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=camera["eye"], target=camera["target"], up=camera["up"]),
            "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "independent"},
        },
    }
    if envmap:
        scene["envmap"] = {"type": "envmap", "filename": envmap}
    for name, (path, with_normals) in parts.items():
        m = mats.get(name, {})
        shape = {"type": "obj", "filename": path, "face_normals": not with_normals, "bsdf": mitsuba_bsdf(m)}
        if any(v > 0 for v in m.get("Ke", [0, 0, 0])):
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": m["Ke"]}}
        scene[name] = shape
    return mi.load_dict(scene)


class MitsubaBench:
    """Mitsuba 3 on the same scene, loaded and JIT-warmed once; None from `load` if missing."""

    @staticmethod
    def load(args, reference_path):
        try:
            import mitsuba as mi
            import numpy  # noqa: F401  (MitsubaBench's arrays; not a dependency of mitsuba)
            mi.set_variant("llvm_ad_rgb")
        except Exception as e:  # not installed, no numpy, or no libLLVM
            print(f"Mitsuba not available ({e}); plotting vkrt only", file=sys.stderr)
            return None
        return MitsubaBench(mi, args, reference_path)

    def __init__(self, mi, args, reference_path):
        import numpy as np
        self.mi, self.np, self.seed = mi, np, args.seed
        self.ref = None if args.make_reference else np.array(mi.Bitmap(reference_path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32), dtype=np.float64)
        self.scene = mitsuba_scene(mi, args.obj, args.mtl, {"eye": args.eye, "target": args.target, "up": args.up, "fov": args.fov},
                                   args.width, args.height, args.out, getattr(args, "envmap", None))
        mi.render(self.scene, spp=1, seed=999)  # warm-up: JIT compilation

    def make_reference(self, spp, path, batch=512):
        """Renders `spp` samples (in batches of `batch`, seeds apart, averaged) to `path`."""
        np, mi = self.np, self.mi
        total, done, k = None, 0, 0
        while done < spp:
            n = min(batch, spp - done)
            img = np.array(mi.render(self.scene, spp=n, seed=10_000 + k), dtype=np.float64)
            total = img * n if total is None else total + img * n
            done, k = done + n, k + 1
            print(f"reference: {done} / {spp} spp", file=sys.stderr, flush=True)
        tmp = path + ".tmp.exr"
        mi.Bitmap((total / spp).astype(np.float32)).write(tmp)
        os.replace(tmp, path)

    def render(self, spp, path):
        """(seconds, relMSE) of one render, written to `path` (EXR) for FLIP."""
        t = time.perf_counter()
        out = self.mi.render(self.scene, spp=spp, seed=self.seed)
        img = self.np.array(out, dtype=self.np.float64)  # forces evaluation
        secs = time.perf_counter() - t
        self.mi.Bitmap(out).write(path)
        ref = self.ref
        return secs, float(self.np.mean((img[..., :3] - ref) ** 2 / (ref ** 2 + 0.01)))


def plot(rows, args):
    """Log-log error against seconds, one curve per renderer, to OUT/time_to_error.png."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot", file=sys.stderr)
        return
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.5))
    from matplotlib.ticker import NullFormatter
    for ax, col, label in ((axes[0], 3, "relMSE vs reference"), (axes[1], 4, "mean HDR-FLIP vs reference")):
        for name in dict.fromkeys(r[0] for r in rows):
            pts = [(r[2], r[col]) for r in rows if r[0] == name and r[col] is not None]
            if pts:
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
        ax.set_xlabel("render seconds")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    ax = axes[0]
    # The figure of merit as guide lines: relMSE x seconds = constant is a line of slope -1.
    xs = [min(r[2] for r in rows), max(r[2] for r in rows)]
    for product in (0.1, 0.01):
        ax.loglog(xs, [product / x for x in xs], ":", color="grey", linewidth=0.8)
        ax.annotate(f"relMSE x s = {product:g}", (xs[1], product / xs[1]), fontsize=7, color="grey", ha="right", va="bottom")
    fig.suptitle(f"{os.path.basename(args.scene)} {args.width}x{args.height}: error vs time\n{getattr(args, 'machine', '')}", fontsize=8)
    for a in axes:
        # Label decades only: minor-tick labels on a short log axis overlap (set last: a
        # loglog call resets the formatters).
        a.xaxis.set_minor_formatter(NullFormatter())
        a.yaxis.set_minor_formatter(NullFormatter())
    # Beside the axes: with eight or more curves a legend inside covers them.
    axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    png = os.path.join(args.out, "time_to_error.png")
    fig.savefig(png, dpi=120, bbox_inches="tight")
    print(f"wrote {png}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="scenes/cornell-measured/cornell.yaml")
    ap.add_argument("--reference", default="../shared/refs/cornell-512.exr")
    ap.add_argument("--width", type=int, default=512)
    ap.add_argument("--height", type=int, default=512)
    ap.add_argument("--spp", type=int, nargs="+", default=[1, 4, 16, 64])
    ap.add_argument("--samplers", nargs="+", default=["zsobol", "sobol"])
    ap.add_argument("--coherence", nargs="+", default=["default"],
                    help="coherent sampling to run each sampler with: default (vkrt's defaults), N (N pixels "
                         "in a row share numbers; 1: none), N/B (N pixels scattered over B x B blocks)")
    ap.add_argument("--sampling", nargs="+", choices=["uniform", "adaptive"], default=["uniform"],
                    help="vkrt sample allocations to run (adaptive: --adaptive, only at 8 spp or more)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=1,
                    help="run every row this many times, interleaved, and keep the shortest time (the machine's speed swings)")
    ap.add_argument("--vkrt", default="target/release/vkrt")
    ap.add_argument("--out", default="target/bench/path")
    ap.add_argument("--no-mitsuba", action="store_true")
    ap.add_argument("--replot", metavar="CSV", help="only redraw the plot from a CSV this tool wrote")
    ap.add_argument("--make-reference", type=int, metavar="SPP",
                    help="only render the reference with Mitsuba at SPP samples per pixel (batches of 512, "
                         "averaged) and write it to --reference")
    # The Mitsuba side needs the OBJ, MTL and camera (the cornell-measured defaults).
    ap.add_argument("--obj", default="scenes/cornell-measured/cornell.obj")
    ap.add_argument("--mtl", default="scenes/cornell-measured/cornell.mtl")
    ap.add_argument("--eye", type=float, nargs=3, default=[278, 273, -800])
    ap.add_argument("--target", type=float, nargs=3, default=[278, 273, 0])
    ap.add_argument("--up", type=float, nargs=3, default=[0, 1, 0])
    ap.add_argument("--fov", type=float, default=39.3077)
    ap.add_argument("--vkrt-camera", action="store_true",
                    help="give vkrt the camera above too (--eye, --target, --up, --fov) instead of its scene's own")
    ap.add_argument("--envmap", metavar="FILE",
                    help="light both renderers with this environment map as well (vkrt --envmap, Mitsuba's envmap emitter)")
    args = ap.parse_args()
    if not args.replot:
        # The inputs this run reads, named up front rather than in a failed render's output.
        needed = [("--envmap", args.envmap)] if args.envmap else []
        needed += [("--scene", args.scene), ("--reference", args.reference)] if not args.make_reference else []
        needed += [("--obj", args.obj), ("--mtl", args.mtl)] if args.make_reference or not args.no_mitsuba else []
        for flag, path in needed:
            if not os.path.exists(path):
                sys.exit(f"{flag}: no such file: {path}")
    os.makedirs(args.out, exist_ok=True)
    if args.replot:
        machine_txt = os.path.join(os.path.dirname(args.replot), "machine.txt")
        if os.path.exists(machine_txt):
            with open(machine_txt) as f:
                args.machine = f.read().strip()
        with open(args.replot, newline="") as f:
            rows = [(r["renderer"], int(r["spp"]), float(r["seconds"]), float(r["relmse"]),
                     float(r["flip_hdr"]) if r.get("flip_hdr") else None) for r in csv.DictReader(f)]
        plot(rows, args)
        return

    if args.make_reference:
        mitsuba = MitsubaBench.load(args, args.reference)
        if mitsuba is None:
            sys.exit("--make-reference needs Mitsuba 3 (pip install mitsuba numpy; libLLVM 19)")
        os.makedirs(os.path.dirname(os.path.abspath(args.reference)), exist_ok=True)
        mitsuba.make_reference(args.make_reference, args.reference)
        print(f"wrote {args.reference}: Mitsuba {mitsuba.mi.__version__}, {args.make_reference} spp")
        return

    configs = [(c, s, a) for c in args.coherence for s in args.samplers for a in args.sampling]
    mitsuba = None if args.no_mitsuba else MitsubaBench.load(args, args.reference)
    args.machine = machine(args.vkrt, mitsuba.mi.__version__ if mitsuba else None)
    print(args.machine, flush=True)
    with open(os.path.join(args.out, "machine.txt"), "w") as f:
        f.write(args.machine + "\n")
    if flip_hdr(args.reference, args.reference) is None:
        print("flip-evaluator or mitsuba not installed (pip install flip-evaluator mitsuba): no FLIP column", file=sys.stderr)
    best = {}  # (renderer, spp) -> [seconds, relMSE, FLIP], in first-run order
    fmt = lambda x: "-" if x is None else f"{x:.4f}"

    def record(r, renderer, label, spp, secs, rel, flip, pipeline=None):
        """Keeps the shortest time of (renderer, spp) and prints the round's row."""
        key = (renderer, spp)
        best[key] = [min(secs, best.get(key, [secs])[0]), rel, flip]
        note = "" if pipeline is None else f" (of which pipeline creation {pipeline:.3f} s)"
        print(f"round {r + 1}: {label} {spp:5d} spp {secs:8.3f} s relMSE {rel:.4e} product {rel * secs:.3e} FLIP {fmt(flip)}{note}", flush=True)

    # vkrt's warm-up, as Mitsuba's (MitsubaBench.__init__): one uncounted render of each
    # configuration (1 spp; 8, the least the ladder runs, with adaptive sampling), so that the
    # shader variant each one uses is in the caches before round 1.
    for coherence, sampler, sampling in configs:
        adaptive = sampling == "adaptive"
        vkrt_render(args.vkrt, args.scene, os.path.join(args.out, "vkrt-warm-up.exr"), args.width, args.height,
                    8 if adaptive else 1, sampler, args.seed, coherence, adaptive, vkrt_scene_flags(args))
    # Every spp of a round runs each vkrt configuration and then Mitsuba, one after the other,
    # so that a swing of the machine's speed (minutes long here) falls on both sides alike.
    for r in range(args.rounds):
        for spp in args.spp:
            for coherence, sampler, sampling in configs:
                adaptive = sampling == "adaptive"
                if adaptive and spp < 8:
                    continue
                name = f"{sampler} {coherence_name(coherence)}" + (" adaptive" if adaptive else "")
                img = os.path.join(args.out, f"vkrt-{sampler}-c{coherence.replace('/', 'x')}{'-adaptive' if adaptive else ''}-{spp}.exr")
                secs, pipeline = vkrt_render(args.vkrt, args.scene, img, args.width, args.height, spp, sampler, args.seed, coherence, adaptive,
                                             vkrt_scene_flags(args))
                rel = vkrt_compare(args.vkrt, img, args.reference)
                record(r, f"vkrt {name} (lavapipe)", f"vkrt {name:24s}", spp, secs, rel, flip_hdr(img, args.reference), pipeline)
            if mitsuba:
                img = os.path.join(args.out, f"mitsuba-{spp}.exr")
                secs, rel = mitsuba.render(spp, img)
                record(r, "mitsuba3 llvm_ad_rgb", "mitsuba", spp, secs, rel, flip_hdr(img, args.reference))
    # Rows by renderer, then spp, as before.
    order = {}
    for (name, spp) in best:
        order.setdefault(name, len(order))
    rows = sorted(((name, spp, secs, rel, flip) for (name, spp), (secs, rel, flip) in best.items()), key=lambda r: (order[r[0]], r[1]))

    csv_path = os.path.join(args.out, "time_to_error.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["renderer", "spp", "seconds", "relmse", "relmse_x_seconds", "flip_hdr"])
        for r in rows:
            w.writerow([r[0], r[1], f"{r[2]:.4f}", f"{r[3]:.6e}", f"{r[2] * r[3]:.4e}", "" if r[4] is None else f"{r[4]:.5f}"])
    print(f"wrote {csv_path}")

    print(f"\n{args.machine}\n\n| renderer | spp | seconds | relMSE | relMSE x s | HDR-FLIP |\n|---|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]:.2f} | {r[3]:.3e} | {r[2] * r[3]:.3e} | {fmt(r[4])} |")

    plot(rows, args)


if __name__ == "__main__":
    main()
