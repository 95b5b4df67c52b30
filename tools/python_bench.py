#!/usr/bin/env python3
"""What the Python package costs next to the command line (issue 42's numbers; a benchmark,
not a test): one render, and `trace` of 1M rays from numpy against `vkrt trace` on the same
.npy file. A and B alternate, ROUNDS rounds; medians.

    tools/python-test                      # builds and installs the package (target/python-venv)
    target/python-venv/bin/python tools/python_bench.py [--rounds 5] [--scene S] [--trace-scene T]

- render: `vkrt render SCENE --integrator path --spp 64` at 512x512 against the same render
  through Python, both as whole processes (interpreter start and `import vkrt` included), and
  inside one Python process (load_scene + render) against the CLI's own "rendered ... in S"
  time plus its load;
- trace: `vkrt trace`'s M rays/s (its upload, sorting, traversal and read-back, no file I/O)
  against `Scene.trace` on the same rays held in numpy, given as the (N, 8) array's column
  views (origins, directions, tmin, tmax: gathered into the device's layout) and as the (N, 8)
  array itself (read in place); its time includes that and making the result's arrays.
"""

import argparse
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import vkrt

ROOT = pathlib.Path(__file__).resolve().parents[1]


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed:\n{r.stderr}")
    return time.perf_counter() - t, r.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--vkrt", default=str(ROOT / "target" / "release" / "vkrt"))
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "cornell-measured" / "cornell.yaml"))
    ap.add_argument("--trace-scene", default=str(ROOT / "scenes" / "bench" / "conference.yaml"))
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--size", type=int, default=512)
    args = ap.parse_args()
    tmp = pathlib.Path(tempfile.mkdtemp())
    n = args.size

    # Render: whole processes, alternating.
    cli_cmd = [args.vkrt, "render", args.scene, "--integrator", "path", "--spp", args.spp, "--width", n, "--height", n, "-o", tmp / "cli.pfm", "-q"]
    py_cmd = [sys.executable, "-c", f"import vkrt; vkrt.render(vkrt.load_scene({args.scene!r}), spp={args.spp}, width={n}, height={n}, progress=False)"]
    run(list(map(str, cli_cmd)))
    run(py_cmd)
    cli_s, py_s = [], []
    for _ in range(args.rounds):
        cli_s.append(run(list(map(str, cli_cmd)))[0])
        py_s.append(run(py_cmd)[0])
    # In one process: load + render, against the CLI's whole process.
    inproc = []
    for _ in range(args.rounds):
        t = time.perf_counter()
        vkrt.render(vkrt.load_scene(args.scene), spp=args.spp, width=n, height=n, progress=False)
        inproc.append(time.perf_counter() - t)
    mc, mp, mi = statistics.median(cli_s), statistics.median(py_s), statistics.median(inproc)
    print(f"render {pathlib.Path(args.scene).name} {n}x{n} {args.spp} spp, median of {args.rounds}:")
    print(f"  CLI process {mc:.3f} s, Python process {mp:.3f} s ({mp / mc:.3f}x), load_scene + render in Python {mi:.3f} s ({mi / mc:.3f}x)")

    # Trace: 1M rays of each kind.
    scene = vkrt.load_scene(args.trace_scene)
    for kind in ("primary", "incoherent"):
        rays_path = tmp / f"{kind}.npy"
        run([args.vkrt, "rays", args.trace_scene, "--kind", kind, "--count", "1048576", "-o", str(rays_path)])
        rays = np.load(rays_path)
        o, d, t0, t1 = rays[:, 0:3], rays[:, 4:7], rays[:, 3], rays[:, 7]
        scene.trace(o, d, t0, t1)  # warm: builds the layout's pipeline
        scene.trace(rays)
        cli_rate, py_rate, packed_rate = [], [], []
        for _ in range(args.rounds):
            _, err = run([args.vkrt, "trace", args.trace_scene, "--rays", str(rays_path), "-o", str(tmp / "hits.npy")])
            m = re.search(r": ([0-9.]+) M rays/s \(upload", err)
            if m is None:
                sys.exit(f"no rate in vkrt trace's output:\n{err}")
            cli_rate.append(float(m.group(1)))
            t = time.perf_counter()
            scene.trace(o, d, t0, t1)
            py_rate.append(len(rays) / (time.perf_counter() - t) / 1e6)
            t = time.perf_counter()
            scene.trace(rays)
            packed_rate.append(len(rays) / (time.perf_counter() - t) / 1e6)
        c, p, q = statistics.median(cli_rate), statistics.median(py_rate), statistics.median(packed_rate)
        print(
            f"trace {pathlib.Path(args.trace_scene).name} {kind}, {len(rays)} rays, median of {args.rounds}: vkrt trace {c:.3f} M rays/s, "
            f"Scene.trace(origins, directions) {p:.3f} ({p / c:.3f}x), Scene.trace(rays) on the (N, 8) array {q:.3f} ({q / c:.3f}x)"
        )


if __name__ == "__main__":
    main()
