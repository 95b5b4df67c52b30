#!/usr/bin/env python3
"""Which sort key lines incoherent rays up best for `vkrt trace`: the upper bound of ray reordering.

Writes one scene's incoherent rays (origins uniform in the bounds, directions uniform on the
sphere, as tools/embree_compare.py makes them) once as generated and once sorted by each
candidate key (numpy, not timed), sorted whole or within windows, and times `vkrt trace
--order given` on every file, the files interleaved over the rounds, best of the rounds.
The key that `--order auto` uses is `dir4+origin4` (host/integrator/ray_order.rs).

Usage: python3 tools/ray_order_keys.py [--vkrt target/release/vkrt] [--rays N] [--rounds R] SCENE.obj
Needs: pip install numpy
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import embree_compare as ec  # noqa: E402


def spread(x, bits, stride):
    x = x.astype(np.uint64)
    r = np.zeros_like(x)
    for b in range(bits):
        r |= ((x >> np.uint64(b)) & np.uint64(1)) << np.uint64(stride * b)
    return r


def origin_cell(o, lo, hi, bits):
    q = ((o - lo) / (hi - lo) * (1 << bits)).clip(0, (1 << bits) - 1).astype(np.uint64)
    return (spread(q[:, 0], bits, 3) << np.uint64(2)) | (spread(q[:, 1], bits, 3) << np.uint64(1)) | spread(q[:, 2], bits, 3)


def direction_cell(d, bits):
    """Octahedral map of the sphere, bits per axis, the two coordinates interleaved."""
    l1 = np.abs(d).sum(1)
    px, py = d[:, 0] / l1, d[:, 1] / l1
    neg = d[:, 2] < 0
    ox = np.where(neg, (1 - np.abs(py)) * np.sign(px), px)
    oy = np.where(neg, (1 - np.abs(px)) * np.sign(py), py)
    n = 1 << bits
    qx = ((ox * 0.5 + 0.5) * n).clip(0, n - 1).astype(np.uint64)
    qy = ((oy * 0.5 + 0.5) * n).clip(0, n - 1).astype(np.uint64)
    return spread(qx, bits, 2) | (spread(qy, bits, 2) << np.uint64(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--vkrt", default="target/release/vkrt")
    ap.add_argument("--rays", type=int, default=1 << 20)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    tris = ec.load_obj(args.scene)
    lo, hi = tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0)
    rays = ec.incoherent_rays(lo, hi, args.rays, np.random.default_rng(1))
    o, d = rays[:, 0:3], rays[:, 4:7]

    def key(dir_bits, origin_bits):
        return (direction_cell(d, dir_bits) << np.uint64(3 * origin_bits)) | origin_cell(o, lo, hi, origin_bits)

    candidates = {
        "as generated": None,
        "origin10 only": origin_cell(o, lo, hi, 10),
        "dir5+origin7": key(5, 7),
        "dir4+origin4": key(4, 4),
        "dir4+origin2": key(4, 2),
        "dir4+origin1": key(4, 1),
        "dir3+origin2": key(3, 2),
    }
    windows = {"dir4+origin4, 64k windows": 1 << 16, "dir4+origin4, 256k windows": 1 << 18}
    tmp = tempfile.mkdtemp(prefix="vkrt-keys-")
    files = {}
    for name, k in candidates.items():
        files[name] = rays if k is None else rays[np.argsort(k, kind="stable")]
    k = key(4, 4)
    for name, w in windows.items():
        out = rays.copy()
        for s in range(0, len(rays), w):
            out[s:s + w] = rays[s:s + w][np.argsort(k[s:s + w], kind="stable")]
        files[name] = out
    paths = {}
    for i, (name, r) in enumerate(files.items()):
        paths[name] = os.path.join(tmp, f"rays{i}.npy")
        np.save(paths[name], r)
    best = {}
    out_path = os.path.join(tmp, "hits.npy")
    for _ in range(args.rounds):
        for name, path in paths.items():
            rate = ec.run_vkrt(args.vkrt, args.scene, path, out_path, "sah", "threaded", "given")[0]
            best[name] = max(best.get(name, 0.0), rate)
    base = best["as generated"]
    print(f"{os.path.basename(args.scene)}: {len(rays)} incoherent rays, SAH / threaded, vkrt trace --order given, best of {args.rounds}")
    print("| ray file order | M rays/s | vs as generated |")
    print("|---|---:|---:|")
    for name, rate in best.items():
        print(f"| {name} | {rate / 1e6:.2f} | {rate / base:.2f}x |")


if __name__ == "__main__":
    main()
