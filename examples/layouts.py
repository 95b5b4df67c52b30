"""Every BVH builder x layout on two scenes, from numpy rays: rays per second and nodes visited
per ray, camera rays and incoherent (diffuse-bounce) rays, as a matplotlib figure.

    pip install ./python matplotlib        # once, from the repository's root
    python examples/layouts.py             # Conference and Sponza (scenes/bench/, which read
                                           # the meshes from ../shared/scenes)
    python examples/layouts.py A.obj B.gltf --out layouts.png

The rays are made here with numpy, not by vkrt: one camera ray per pixel of a 512 x 384 image
from each scene's camera, and from the points those rays hit, one ray in a direction uniform
on the sphere (incoherent rays, as a path tracer's bounces are). Each
builder x layout traces the same rays; times are the best of three calls, the device's work
only (the rays are already in memory).
"""

import argparse
import pathlib
import time

import numpy as np
import vkrt

ROOT = pathlib.Path(__file__).resolve().parents[1]
DEFAULT_SCENES = [ROOT / "scenes" / "bench" / "conference.yaml", ROOT / "scenes" / "bench" / "sponza.yaml"]


def camera_rays(camera, width, height):
    """One pinhole ray through each pixel centre, row by row from the top."""
    eye, target, up = (np.array(camera[k], np.float64) for k in ("eye", "target", "up"))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    half_h = np.tan(np.radians(camera["fov"]) / 2)
    half_w = half_h * width / height
    xs = ((np.arange(width) + 0.5) / width * 2 - 1) * half_w
    ys = (1 - (np.arange(height) + 0.5) / height * 2) * half_h
    gx, gy = np.meshgrid(xs, ys)
    d = forward + gx[..., None] * right + gy[..., None] * true_up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    origins = np.broadcast_to(eye, d.shape).reshape(-1, 3)
    return origins.astype(np.float32), d.reshape(-1, 3).astype(np.float32)


def best_time(fn, runs=3):
    best, out = np.inf, None
    for _ in range(runs):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def study(path, width, height, rng):
    rows = []
    first = vkrt.load_scene(path)
    origins, directions = camera_rays(first.camera, width, height)
    # Incoherent rays: from each camera ray's hit, a direction uniform on the sphere, starting
    # a little past the surface (tmin) so that a ray into the surface goes on behind it.
    hits = first.trace(origins, directions)
    hit = hits["prim"] != 0xFFFFFFFF
    points = origins[hit] + directions[hit] * hits["t"][hit, None]
    d = rng.normal(size=points.shape)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    tmin = 1e-4 * float(np.abs(points).max())
    bounce = (points.astype(np.float32), d.astype(np.float32))
    for builder in vkrt.BUILDERS:
        scene = vkrt.load_scene(path, builder=builder)
        for layout in vkrt.LAYOUTS:
            row = {"scene": pathlib.Path(path).stem, "builder": builder, "layout": layout}
            for kind, (o, d) in (("camera", (origins, directions)), ("incoherent", bounce)):
                scene.trace(o[:1024], d[:1024], tmin=tmin, layout=layout)  # builds the layout's tree once
                t0 = tmin if kind == "incoherent" else 0.0
                seconds, h = best_time(lambda: scene.trace(o, d, tmin=t0, layout=layout))
                row[f"{kind}_mrays_per_s"] = len(o) / seconds / 1e6
                row[f"{kind}_nodes_per_ray"] = float(h["nodes"].mean())
            rows.append(row)
            print(
                f"{row['scene']:>12} {builder:>11} {layout:>11}: camera {row['camera_mrays_per_s']:6.2f} M rays/s "
                f"{row['camera_nodes_per_ray']:5.1f} nodes, incoherent {row['incoherent_mrays_per_s']:6.2f} M rays/s "
                f"{row['incoherent_nodes_per_ray']:5.1f} nodes",
                flush=True,
            )
    return rows


def plot(rows, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = sorted({r["scene"] for r in rows}, key=[r["scene"] for r in rows].index)
    fig, axes = plt.subplots(len(scenes), 2, figsize=(12, 3.6 * len(scenes)), squeeze=False)
    width = 0.8 / len(vkrt.LAYOUTS)
    for i, scene in enumerate(scenes):
        for j, (metric, label) in enumerate((("mrays_per_s", "M rays/s (higher is better)"), ("nodes_per_ray", "nodes visited per ray"))):
            ax = axes[i][j]
            for k, layout in enumerate(vkrt.LAYOUTS):
                for m, kind in enumerate(("camera", "incoherent")):
                    values = [next(r for r in rows if r["scene"] == scene and r["builder"] == b and r["layout"] == layout)[f"{kind}_{metric}"] for b in vkrt.BUILDERS]
                    x = np.arange(len(vkrt.BUILDERS)) + (k - len(vkrt.LAYOUTS) / 2 + 0.5) * width
                    ax.bar(
                        x + (m - 0.5) * width / 2,
                        values,
                        width / 2,
                        color=f"C{k}",
                        alpha=1.0 if kind == "camera" else 0.5,
                        label=f"{layout} ({kind})" if i == 0 and j == 0 else None,
                    )
            ax.set_xticks(np.arange(len(vkrt.BUILDERS)), vkrt.BUILDERS)
            ax.set_title(f"{scene}: {label}")
    fig.legend(loc="lower center", ncol=5, fontsize=8)
    fig.suptitle(f"vkrt builders x layouts on {vkrt.devices()[[d['default'] for d in vkrt.devices()].index(True)]['name']} (solid: camera rays, pale: incoherent)")
    fig.tight_layout(rect=(0, 0.08, 1, 0.96))
    fig.savefig(out, dpi=90)
    print(f"wrote {out}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="*", default=DEFAULT_SCENES, help="two (or more) scene files")
    parser.add_argument("--out", default="layouts.png", help="the figure (PNG)")
    parser.add_argument("--width", type=int, default=512)
    parser.add_argument("--height", type=int, default=384)
    args = parser.parse_args()
    rng = np.random.default_rng(1)
    rows = [row for path in args.scenes for row in study(path, args.width, args.height, rng)]
    plot(rows, args.out)


if __name__ == "__main__":
    main()
