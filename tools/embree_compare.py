#!/usr/bin/env python3
"""Ray throughput of vkrt (on its Vulkan device, e.g. lavapipe) and of Embree 4 (PyPI `embreex`)
on the same rays, in the same run, so the numbers compare on a shared machine.

For each scene: writes primary rays (a 1024x1024 pinhole at the centre of the bounds looking
along the widest horizontal axis: coherent, interior view) and incoherent rays (origins uniform
in the bounds, directions uniform on the sphere) as (N, 8) float32 .npy files; times
`vkrt trace` on them (rays/s over upload, traversal and read-back, as vkrt prints it) and
Embree's closest-hit query (`EmbreeScene.run`, rays/s over the call) on one thread and on
`--embree-threads` threads at once (default: every core, the same cores lavapipe uses; each
thread runs one call on its own contiguous share of the rays, and embreex releases the GIL
inside the call); and reports how often vkrt and Embree agree on the hit triangle.

With `--ray-query BIN` (`cargo build --release -p vkrt-bench --bin vkrt-ray-query`) it also
times the Vulkan driver's own ray tracing on the same rays (`VK_KHR_ray_query` over a BVH the
driver builds: an anchor through the same compiler, not a product path; the tool's doc says
more), over upload, traversal and read-back as vkrt's rate is, and with the driver's
traversal-only rate beside it.

The OBJ is read here with the same rules as vkrt's loader (polygons fan-triangulated in file
order, zero-area triangles dropped), so triangle ids match between the two.

Usage: python3 tools/embree_compare.py [--vkrt target/release/vkrt] [--builder B] [--layout L (default: vkrt's)]
       [--rays N] [--orders auto given ...] [--rounds R] [--embree-threads T]
       [--ray-query target/release/vkrt-ray-query] SCENE.obj...
With several `--orders` (vkrt trace --order) each ray set is traced once per order, so the
rows compare inside one run; `--rounds` repeats every timing and keeps the best.
Needs: pip install embreex numpy
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np


def load_obj(path):
    """Triangles (n, 3, 3) float32, fan-triangulated in file order, zero-area ones dropped."""
    verts, faces = [], []
    with open(path, "r", errors="replace") as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = []
                for tok in line.split()[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    v = np.asarray(verts, dtype=np.float32)
    tris = v[np.asarray(faces, dtype=np.int64)]
    area2 = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
    return tris[area2 > 0]


def primary_rays(lo, hi, size):
    centre, ext = (lo + hi) / 2, hi - lo
    axis = 0 if ext[0] >= ext[2] else 2
    fwd = np.zeros(3, np.float32); fwd[axis] = 1
    up = np.array([0, 1, 0], np.float32)
    right = np.cross(fwd, up)
    j, i = np.mgrid[0:size, 0:size].astype(np.float32)
    x = ((i + 0.5) / size * 2 - 1) * np.tan(np.radians(30))
    y = (1 - (j + 0.5) / size * 2) * np.tan(np.radians(30))
    d = fwd + x[..., None] * right + y[..., None] * up
    d = (d / np.linalg.norm(d, axis=-1, keepdims=True)).reshape(-1, 3)
    o = np.broadcast_to(centre, d.shape)
    return pack(o, d)


def incoherent_rays(lo, hi, n, rng):
    o = lo + rng.random((n, 3), dtype=np.float32) * (hi - lo)
    z = rng.uniform(-1, 1, n).astype(np.float32)
    phi = rng.uniform(0, 2 * np.pi, n).astype(np.float32)
    r = np.sqrt(np.maximum(0, 1 - z * z))
    d = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    return pack(o, d)


def pack(o, d):
    rays = np.zeros((len(d), 8), np.float32)
    rays[:, 0:3], rays[:, 4:7], rays[:, 7] = o, d, np.inf
    return rays


def run_vkrt(vkrt, scene, rays_path, out_path, builder, layout, order):
    cmd = [vkrt, "trace", scene, "--rays", rays_path, "--out", out_path, "--builder", builder, "--order", order]
    if layout is not None:
        cmd += ["--layout", layout]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"vkrt trace failed: {res.stderr}")
    m = re.search(r"([0-9.]+) M rays/s.*?([0-9.]+) nodes visited and ([0-9.]+) triangles", res.stderr)
    return float(m.group(1)) * 1e6, float(m.group(2)), float(m.group(3)), np.load(out_path)


def run_ray_query(tool, scene, rays_path, out_path):
    """The driver's ray query on the rays: (rays/s end to end, rays/s traversal, hits)."""
    res = subprocess.run([tool, scene, rays_path, "--out", out_path, "--rounds", "1"], capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"{tool} failed: {res.stderr}")
    m = re.search(r"([0-9.]+) M rays/s \(traversal\), ([0-9.]+) M rays/s \(upload", res.stdout)
    return float(m.group(2)) * 1e6, float(m.group(1)) * 1e6, np.load(out_path)


def embree_run(es, o, d, threads):
    """Embree's closest hits for rays (o, d) on `threads` threads at once, and the seconds
    from the first call's start to the last one's end."""
    # Contiguous slices are views: no copy inside the timed span.
    o_parts, d_parts = np.array_split(o, threads), np.array_split(d, threads)
    results = [None] * threads

    def work(k):
        results[k] = es.run(o_parts[k], d_parts[k], output=1)

    workers = [threading.Thread(target=work, args=(k,)) for k in range(threads)]
    t0 = time.perf_counter()
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    seconds = time.perf_counter() - t0
    return np.concatenate([r["primID"] for r in results]), seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--vkrt", default="target/release/vkrt")
    ap.add_argument("--builder", default="reinsertion")
    ap.add_argument("--layout", default=None, help="vkrt trace --layout (default: vkrt's own default)")
    ap.add_argument("--rays", type=int, default=1 << 20, help="incoherent rays per scene")
    ap.add_argument("--orders", nargs="+", default=["auto"], help="vkrt trace --order values, one row each")
    ap.add_argument("--rounds", type=int, default=1, help="timings per row; the best is kept")
    ap.add_argument("--embree-threads", type=int, default=os.cpu_count() or 1,
                    help="threads for Embree's many-core column (default: every core)")
    ap.add_argument("--ray-query", default=None, metavar="BIN",
                    help="also time the driver's VK_KHR_ray_query on the same rays with this vkrt-ray-query binary")
    args = ap.parse_args()
    if args.embree_threads < 1:
        sys.exit("--embree-threads must be at least 1")
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    rng = np.random.default_rng(1)
    tmp = tempfile.mkdtemp(prefix="vkrt-embree-")
    n = args.embree_threads
    print(f"vkrt: {args.builder} / {args.layout or 'its default layout'}; Embree 4 via embreex on 1 and on {n} threads")
    print(f"| scene | triangles | rays | kind | vkrt order | vkrt M rays/s | Embree 1 thread | Embree {n} threads | "
          f"vkrt / Embree {n} threads | nodes/ray | tris/ray | same prim |"
          + (" driver ray query M rays/s (traversal alone) | vkrt / ray query | same prim (ray query) |" if args.ray_query else ""))
    print("|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|" + ("---:|---:|---:|" if args.ray_query else ""))
    for scene in args.scenes:
        tris = load_obj(scene)
        lo, hi = tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0)
        es = rtcore_scene.EmbreeScene()
        TriangleMesh(es, tris)
        es.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))  # build the BVH now
        for kind, rays in (("primary", primary_rays(lo, hi, 1024)), ("incoherent", incoherent_rays(lo, hi, args.rays, rng))):
            rays_path, out_path = os.path.join(tmp, "rays.npy"), os.path.join(tmp, "hits.npy")
            np.save(rays_path, rays)
            o, d = np.ascontiguousarray(rays[:, 0:3]), np.ascontiguousarray(rays[:, 4:7])
            # Rounds interleave Embree and every vkrt order, so a slow phase of the machine
            # hits all of them.
            em_rate, em_many, vk, rq = 0.0, 0.0, {}, None
            for _ in range(args.rounds):
                if args.ray_query:
                    r = run_ray_query(args.ray_query, scene, rays_path, out_path)
                    if rq is None or r[0] > rq[0]:
                        rq = r
                em_prim, seconds = embree_run(es, o, d, 1)
                em_rate = max(em_rate, len(rays) / seconds)
                many_prim, seconds = embree_run(es, o, d, n)
                em_many = max(em_many, len(rays) / seconds)
                if not np.array_equal(em_prim, many_prim):
                    sys.exit("Embree's threaded run disagrees with its single-threaded one")
                for order in args.orders:
                    rate, nodes, tests, hits = run_vkrt(args.vkrt, scene, rays_path, out_path, args.builder, args.layout, order)
                    if order not in vk or rate > vk[order][0]:
                        vk[order] = (rate, nodes, tests, hits)
            em_prim = em_prim.astype(np.int64)
            for order in args.orders:
                vk_rate, nodes, tests, hits = vk[order]
                vk_prim = np.where(hits["prim"] == 0xFFFFFFFF, -1, hits["prim"].astype(np.int64))
                same = float(np.mean(em_prim == vk_prim))
                row = (f"| {os.path.basename(scene)} | {len(tris)} | {len(rays)} | {kind} | {order} | {vk_rate / 1e6:.2f} | "
                       f"{em_rate / 1e6:.2f} | {em_many / 1e6:.2f} | {vk_rate / em_many:.2f} | {nodes:.1f} | {tests:.2f} | {same * 100:.2f}% |")
                if rq is not None:
                    rq_prim = np.where(rq[2]["prim"] == 0xFFFFFFFF, -1, rq[2]["prim"].astype(np.int64))
                    row += (f" {rq[0] / 1e6:.3f} ({rq[1] / 1e6:.3f}) | {vk_rate / rq[0]:.1f} | "
                            f"{float(np.mean(rq_prim == vk_prim)) * 100:.2f}% |")
                print(row)


if __name__ == "__main__":
    main()
