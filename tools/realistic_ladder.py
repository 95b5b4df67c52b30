#!/usr/bin/env python3
"""The path tracer's 16 / 64 / 256 spp ladder against Mitsuba 3 on five realistic scenes, in the
style of tools/path_ladder.py (which does the Cornell boxes): Sponza (an atrium lit by a
sun-and-sky environment map through its open roof), Sibenik (a cathedral nave lit by an emissive
strip under its vault: its windows are closed), Conference (a closed room lit by three ceiling
area lights), and the Stanford dragon and Happy Buddha (100k-triangle objects on a ground quad
under the same map), all 320x240. Each scene runs through tools/path_time_to_error.py
(--rounds 2 by default: shortest of two interleaved rounds) against a Mitsuba reference (2048
spp by default), and one summary follows: per scene and sample count, relMSE x seconds of vkrt
over Mitsuba's and HDR-FLIP at equal time (Mitsuba's FLIP log-log interpolated at vkrt's time,
as path_ladder.py does), with the machine named; also written to OUT/summary.md.

The scenes are written by this tool to target/bench/realistic/<name>/<name>.obj + .mtl, so that
both renderers see exactly the same thing: the shared models' positions and faces only (no
normals, texture coordinates or textures: flat shading), fan-triangulated, with the triangles
that vkrt drops as zero-area (its f32 rule, host/scene/assemble.rs) left out so that the two
count the same triangles, and plain diffuse (Lambert) materials; plus, per scene, a ground quad
or emissive rectangles (MTL Ke). The sun-and-sky map is tests/refs/envmap-sun.exr (vkrt's
--envmap follows Mitsuba's lat-long convention, so Mitsuba's `envmap` emitter takes it with the
identity transform). vkrt runs with its defaults apart from the scene, camera, size, spp and
map. A second table gives the mean of vkrt's and Mitsuba's most-sampled images over the
reference's: both should be within noise of 1 (a check that the two render the same scene).

References are kept in target/bench/realistic/refs/, named by scene, size, spp and a hash of the
scene's files, camera and map, and made only when absent (Mitsuba, in batches of 512 spp: at
2048 spp some minutes per scene on a small machine; Conference takes longest).

A benchmark, not a test: its numbers compare only inside one run on one machine (BENCHMARKS.md).

Usage (from anywhere, after `cargo build --release`; needs ../shared/scenes beside the
repository, PyPI mitsuba, numpy and flip-evaluator, and libLLVM 19 for Mitsuba's llvm_ad_rgb:
Debian 12 `libllvm19`; the scene preparation alone needs only the standard library):
  python3 tools/realistic_ladder.py [--scenes sponza sibenik conference dragon buddha]
      [--spp 16 64 256] [--rounds 2] [--reference-spp 2048] [--out target/bench/realistic-ladder]
  python3 tools/realistic_ladder.py --prepare-only      # only write the scenes
A quick check at a small size: --size 64 48 --spp 16 --rounds 1 --reference-spp 64 (FLIP at
equal time needs two or more sample counts: with one it shows "-").
"""
import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
from array import array

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from path_ladder import summary as ladder_rows  # noqa: E402  (the same table as the boxes')

SHARED = "../shared/scenes"
ENVMAP = "tests/refs/envmap-sun.exr"
PREPARED = "target/bench/realistic"


def conference_lights():
    """Three 360 x 240 emitters along the room's long (x) axis, 10 units below its lower ceiling
    (y 630.66; the room spans x -470..1650 and z -1016..595 with an alcove beyond x -470, its
    floor at y 0, the table top at y 178 around x 400..800)."""
    return [((x, 620.0, -210.0), (180.0, 120.0)) for x in (-100.0, 590.0, 1280.0)]


# name: source OBJ, material (Kd) of the model, camera (eye, target, up, vertical fov), whether
# the envmap lights it, emissive rectangles ((centre), (half x, half z)) facing down with their
# Ke, and a ground quad's Kd (None: no ground).
SCENES = {
    # The map's sun (u 0.3, v 0.306) shines from +x (and a little +z) at 35 degrees elevation:
    # down the atrium's long axis, onto its far (-x) end as this camera looks along it.
    "sponza": dict(src=f"{SHARED}/sponza-dabrovic/sponza.obj", kd=(0.6, 0.6, 0.6),
                   eye=(13.5, 1.8, -0.6), target=(-12.0, 5.5, 0.6), up=(0, 1, 0), fov=60.0,
                   envmap=True, lights=[], ke=None, ground=None),
    # Its windows are closed in this model: the envmap alone leaves the inside black (mean 7e-5),
    # so an emissive strip 2 units under the nave's barrel vault (3.7 to 4.1 over |z| < 1.5;
    # the nave runs from the door at x -20 to the crossing at x 0, floor at y -15.3) lights it.
    "sibenik": dict(src=f"{SHARED}/sibenik/sibenik.obj", kd=(0.6, 0.6, 0.6),
                    eye=(-17.0, -11.5, 0.0), target=(10.0, -8.0, 0.0), up=(0, 1, 0), fov=60.0,
                    envmap=False, lights=[((-10.0, 2.0, 0.0), (7.0, 1.5))], ke=(6.0, 6.0, 6.0), ground=None),
    "conference": dict(src=f"{SHARED}/conference/conference.obj", kd=(0.6, 0.6, 0.6),
                       eye=(1500.0, 330.0, -210.0), target=(-900.0, 180.0, -210.0), up=(0, 1, 0), fov=60.0,
                       envmap=False, lights=conference_lights(), ke=(8.0, 8.0, 8.0), ground=None),
    "dragon": dict(src=f"{SHARED}/stanford-dragon-100k/dragon.obj", kd=(0.7, 0.6, 0.5),
                   eye=(9.0, 9.0, 20.0), target=(0.0, 4.0, 0.0), up=(0, 1, 0), fov=40.0,
                   envmap=True, lights=[], ke=None, ground=(0.5, 0.5, 0.5)),
    "buddha": dict(src=f"{SHARED}/happy-buddha-100k/buddha.obj", kd=(0.7, 0.6, 0.5),
                   eye=(6.0, 7.0, 16.0), target=(0.0, 4.8, 0.0), up=(0, 1, 0), fov=40.0,
                   envmap=True, lights=[], ke=None, ground=(0.5, 0.5, 0.5)),
}


def read_obj(path):
    """(positions, triangles) of an OBJ: `v` lines' x y z, and every face fan-triangulated in
    file order (as vkrt does) into 0-based index triples. Texture coordinates, normals,
    materials and groups are ignored; CRLF line endings are fine (universal newlines)."""
    verts, tris = [], []
    with open(path, encoding="latin-1") as f:
        for lineno, line in enumerate(f, 1):
            p = line.split()
            if not p:
                continue
            try:
                if p[0] == "v":
                    verts.append((float(p[1]), float(p[2]), float(p[3])))
                elif p[0] == "f":
                    idx = []
                    for corner in p[1:]:
                        i = int(corner.split("/")[0])
                        i = i - 1 if i > 0 else len(verts) + i
                        if not 0 <= i < len(verts):
                            raise ValueError(f"vertex {corner} out of range")
                        idx.append(i)
                    tris += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
            except (ValueError, IndexError) as e:
                sys.exit(f"{path}:{lineno}: cannot read {line.strip()!r}: {e}")
    if not tris:
        sys.exit(f"{path}: no faces")
    return verts, tris


def vkrt_keeps(verts, tris):
    """Which triangles vkrt keeps: it drops those whose edge cross product (p1 - p0) x (p2 - p0),
    in f32, has a length that is zero or not finite (host/scene/assemble.rs). Emulated in f32
    here (array('f') rounds each step), since some triangles are zero-area only in f32."""
    f32 = lambda xs: array("f", xs).tolist()
    p = [f32([v[k] for v in verts]) for k in range(3)]
    corner = lambda j, k: [p[k][t[j]] for t in tris]
    e1 = [f32([b - a for a, b in zip(corner(0, k), corner(1, k))]) for k in range(3)]
    e2 = [f32([c - a for a, c in zip(corner(0, k), corner(2, k))]) for k in range(3)]

    def component(i, j):  # e1[i] * e2[j] - e1[j] * e2[i], each step rounded to f32
        return f32([a - b for a, b in zip(f32([x * y for x, y in zip(e1[i], e2[j])]),
                                          f32([x * y for x, y in zip(e1[j], e2[i])]))])
    cx, cy, cz = component(1, 2), component(2, 0), component(0, 1)
    sq = lambda c: f32([x * x for x in c])
    dot = f32([a + b for a, b in zip(f32([a + b for a, b in zip(sq(cx), sq(cy))]), sq(cz))])
    return [d > 0.0 and d != math.inf for d in dot]


def quad(centre, half_x, half_z, up):
    """Four corners of a horizontal rectangle, wound so that its normal points up (or down)."""
    x, y, z = centre
    corners = [(x - half_x, y, z - half_z), (x - half_x, y, z + half_z), (x + half_x, y, z + half_z), (x + half_x, y, z - half_z)]
    return corners if up else corners[::-1]


def fmt(x):
    return repr(float(x))


def write_if_changed(path, text):
    """Writes `text` to `path` unless it already holds exactly that (so that vkrt's prepared-
    scene cache, keyed on the files, stays valid between runs)."""
    data = text.encode()
    if os.path.exists(path):
        with open(path, "rb") as f:
            if f.read() == data:
                return
    with open(path + ".tmp", "wb") as f:
        f.write(data)
    os.replace(path + ".tmp", path)


def prepare(name, spec):
    """Writes PREPARED/name/name.obj and .mtl; returns (obj, mtl, triangles written, zero-area
    triangles left out)."""
    verts, tris = read_obj(spec["src"])
    keep = vkrt_keeps(verts, tris)
    tris = [t for t, k in zip(tris, keep) if k]
    dropped = len(keep) - len(tris)
    folder = os.path.join(PREPARED, name)
    os.makedirs(folder, exist_ok=True)
    obj, mtl = os.path.join(folder, f"{name}.obj"), os.path.join(folder, f"{name}.mtl")
    lines = [f"# {name}: generated by tools/realistic_ladder.py from {spec['src']}",
             f"# positions and faces only, fan-triangulated; {dropped} zero-area triangles (vkrt's f32 rule) left out",
             f"mtllib {name}.mtl"]
    lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in verts]
    lines.append("usemtl model")
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in tris]
    count = len(tris)
    mtl_lines = [f"# {name}: generated by tools/realistic_ladder.py", "newmtl model", "Kd " + " ".join(map(fmt, spec["kd"]))]

    def add_quad(corners, material):
        nonlocal count
        base = len(verts) + 1
        verts.extend(corners)
        lines.append(f"usemtl {material}")
        lines.extend(f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in corners)
        lines.extend([f"f {base} {base + 1} {base + 2}", f"f {base} {base + 2} {base + 3}"])
        count += 2

    if spec["ground"]:
        # A ground quad 16 model sizes wide, its top at the model's lowest point.
        lo = [min(v[k] for v in verts) for k in range(3)]
        hi = [max(v[k] for v in verts) for k in range(3)]
        half = 8.0 * max(h - l for h, l in zip(hi, lo))
        add_quad(quad(((lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2), half, half, up=True), "ground")
        mtl_lines += ["newmtl ground", "Kd " + " ".join(map(fmt, spec["ground"]))]
    for centre, (hx, hz) in spec["lights"]:
        add_quad(quad(centre, hx, hz, up=False), "light")
    if spec["lights"]:
        mtl_lines += ["newmtl light", "Kd 0 0 0", "Ke " + " ".join(map(fmt, spec["ke"]))]
    write_if_changed(obj, "\n".join(lines) + "\n")
    write_if_changed(mtl, "\n".join(mtl_lines) + "\n")
    return obj, mtl, count, dropped


def tool_flags(spec, obj, mtl, width, height):
    """path_time_to_error.py's flags for a prepared scene: both renderers get the camera and map."""
    vec = lambda v: [fmt(x) for x in v]
    flags = ["--scene", obj, "--obj", obj, "--mtl", mtl, "--vkrt-camera",
             "--eye", *vec(spec["eye"]), "--target", *vec(spec["target"]), "--up", *vec(spec["up"]),
             "--fov", fmt(spec["fov"]), "--width", str(width), "--height", str(height)]
    return flags + (["--envmap", ENVMAP] if spec["envmap"] else [])


def reference_path(name, spec, obj, mtl, width, height, spp):
    """refs/NAME-WxH-SPPspp-HASH.exr: the hash covers the scene's files, camera and map, so that
    a changed scene makes a new reference rather than reusing a stale one."""
    h = hashlib.sha256()
    for path in [obj, mtl] + ([ENVMAP] if spec["envmap"] else []):
        with open(path, "rb") as f:
            h.update(f.read())
    h.update(json.dumps([spec["eye"], spec["target"], spec["up"], spec["fov"]]).encode())
    return os.path.join(PREPARED, "refs", f"{name}-{width}x{height}-{spp}spp-{h.hexdigest()[:10]}.exr")


def tool(name, args):
    cmd = [sys.executable, os.path.join(HERE, "path_time_to_error.py"), *args]
    print("+", " ".join(cmd), flush=True)
    if subprocess.run(cmd, cwd=ROOT).returncode != 0:
        sys.exit(f"{name}: path_time_to_error.py failed (its message is above): {' '.join(cmd)}")


def mean_ratio(vkrt, image, reference):
    """Mean of `image` over the reference's (all channels), by `vkrt compare`; None if absent."""
    if not os.path.exists(image):
        return None
    res = subprocess.run([vkrt, "compare", "--json", image, reference], capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"vkrt compare failed on {image}:\n{res.stderr}")
    m = json.loads(res.stdout)
    return sum(m["mean"]) / sum(m["reference_mean"]) if sum(m["reference_mean"]) > 0 else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", nargs="+", choices=list(SCENES), default=list(SCENES), metavar="NAME",
                    help=f"scenes to run, of {' '.join(SCENES)} (default: all)")
    ap.add_argument("--spp", nargs="+", default=["16", "64", "256"])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--reference-spp", type=int, default=2048)
    ap.add_argument("--size", type=int, nargs=2, default=[320, 240], metavar=("W", "H"))
    ap.add_argument("--out", default="target/bench/realistic-ladder")
    ap.add_argument("--vkrt", default="target/release/vkrt")
    ap.add_argument("--prepare-only", action="store_true", help="only write the scenes' OBJ and MTL files")
    args = ap.parse_args()
    os.chdir(ROOT)
    width, height = args.size
    # Every input first, so that a missing one stops the run before hours of rendering.
    needed = [(spec["src"], f"{name}'s model; ../shared/scenes must be beside the repository")
              for name, spec in SCENES.items() if name in args.scenes]
    if any(SCENES[n]["envmap"] for n in args.scenes):
        needed.append((ENVMAP, "the environment map"))
    if not args.prepare_only:
        needed.append((args.vkrt, "the vkrt binary: cargo build --release"))
    for path, what in needed:
        if not os.path.exists(path):
            sys.exit(f"missing input: {path} ({what})")

    prepared = {}
    for name in args.scenes:
        obj, mtl, count, dropped = prepare(name, SCENES[name])
        print(f"{name}: {obj}, {count} triangles ({dropped} zero-area left out)", flush=True)
        prepared[name] = (obj, mtl)
    if args.prepare_only:
        return

    results, means, machine = [], {}, None
    for name in args.scenes:
        spec, (obj, mtl) = SCENES[name], prepared[name]
        flags = tool_flags(spec, obj, mtl, width, height)
        ref = reference_path(name, spec, obj, mtl, width, height, args.reference_spp)
        if not os.path.exists(ref):
            tool(name, [*flags, "--reference", ref, "--make-reference", str(args.reference_spp),
                        "--out", os.path.join(PREPARED, name, "mitsuba")])
        out = os.path.join(args.out, name)
        tool(name, [*flags, "--reference", ref, "--spp", *args.spp, "--samplers", "zsobol", "--rounds", str(args.rounds),
                    "--vkrt", args.vkrt, "--out", out])
        results += ladder_rows(name, os.path.join(out, "time_to_error.csv"))
        top = max(args.spp, key=int)
        means[name] = (mean_ratio(args.vkrt, os.path.join(out, f"vkrt-zsobol-cdefault-{top}.exr"), ref),
                       mean_ratio(args.vkrt, os.path.join(out, f"mitsuba-{top}.exr"), ref), top)
        if machine is None and os.path.exists(os.path.join(out, "machine.txt")):
            with open(os.path.join(out, "machine.txt")) as f:
                machine = f.read().strip()

    f = lambda x: f"{x:.4f}" if x is not None else "-"
    lines = [f"Realistic scenes, {width}x{height}, Mitsuba references at {args.reference_spp} spp, "
             f"shortest of {args.rounds} round(s)", "",
             "| scene | spp | relMSE x s, vkrt / Mitsuba | HDR-FLIP vkrt | Mitsuba's at vkrt's time | FLIP at equal time |",
             "|---|---:|---:|---:|---:|---:|"]
    for name, spp, ratio, flip, at in results:
        diff = f"{(flip / at - 1) * 100:+.0f} %" if flip is not None and at else "-"
        lines.append(f"| {name} | {spp} | {ratio:.3f}x | {f(flip)} | {f(at)} | {diff} |")
    lines += ["", "| scene | spp | mean vkrt / reference | mean Mitsuba / reference |", "|---|---:|---:|---:|"]
    for name, (v, m, top) in means.items():
        lines.append(f"| {name} | {top} | {f(v)} | {f(m)} |")
    worst = max(r[2] for r in results) if results else float("nan")
    lines += ["", f"worst relMSE x s ratio {worst:.3f}x (lower is better: vkrt's error x time over Mitsuba's)",
              "", machine or "machine: not recorded"]
    text = "\n".join(lines)
    print("\n" + text)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "summary.md"), "w") as fh:
        fh.write(text + "\n")
    print(f"\nwrote {os.path.join(args.out, 'summary.md')}")


if __name__ == "__main__":
    main()
