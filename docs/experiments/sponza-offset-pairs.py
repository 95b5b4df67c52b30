#!/usr/bin/env python3
"""Two vkrt binaries (say main and a throwaway build with another ray-origin offset) on the
realistic ladder's Sponza (scene, camera, map, 320x240) at the same seeds, so that each pair
shares its sample numbers and the ratio of their sums is nearly free of noise: the ratio of B's
sum to A's over the dim pixels (the 2048-spp reference's luminance 0.01-0.05) and over all
pixels, mean and standard error over the seeds. Needs the reference
(tools/realistic_ladder.py --scenes sponza --reference-spp 2048), mitsuba (to read EXR) and numpy:

    python3 docs/experiments/sponza-offset-pairs.py A_BINARY B_BINARY [SEEDS [SPP]]
"""
import sys, os, statistics, tempfile
import sponza_setup as sp
sp.mi.set_variant("scalar_rgb")
A, B = sys.argv[1], sys.argv[2]
SEEDS = int(sys.argv[3]) if len(sys.argv) > 3 else 6
SPP = int(sys.argv[4]) if len(sys.argv) > 4 else 32
WORK = tempfile.mkdtemp(prefix="vkrt-sponza-pairs-")
_, dim = sp.reference_and_dim()
ratios = []
for seed in range(11, 11 + SEEDS):
    sums = []
    for binary in (A, B):
        img = sp.render_vkrt(binary, seed, SPP, os.path.join(WORK, "img.exr"))
        sums.append((img[dim].sum(), img.sum()))
    ratios.append((sums[1][0] / sums[0][0], sums[1][1] / sums[0][1]))
    print(f"seed {seed}: B / A dim {ratios[-1][0]:.5f} all {ratios[-1][1]:.5f}", flush=True)
for i, label in ((0, "dim pixels"), (1, "all pixels")):
    r = [x[i] for x in ratios]
    print(f"B / A, {label}: {statistics.mean(r):.5f} +- {statistics.stdev(r) / len(r) ** 0.5:.5f}")
