#!/usr/bin/env python3
"""Writes an .npy of rays (N, 8) <f4 for vkrt trace: origins in [lo, hi]^3, mixed directions
(axis-parallel, two-zero-component and uniform), some with tmin > 0 or finite tmax.
Usage: rays.py OUT.npy COUNT LO HI SEED [nan]   (nan: every ray gets a NaN direction component)"""
import random, struct, sys, math
out, n, lo, hi, seed = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
nan = len(sys.argv) > 6 and sys.argv[6] == "nan"
r = random.Random(seed)
rows = []
for i in range(n):
    o = [r.uniform(lo, hi) for _ in range(3)]
    k = i % 10
    if k == 0:
        d = [0.0, 0.0, 0.0]; d[r.randrange(3)] = r.choice([-1.0, 1.0])
    elif k == 1:
        d = [r.choice([-1.0, 1.0]), r.choice([-1.0, 1.0]), 0.0]
    else:
        z = r.uniform(-1, 1); p = r.uniform(0, 2 * math.pi); s = math.sqrt(1 - z * z)
        d = [s * math.cos(p), s * math.sin(p), z]
    tmin = 0.0 if k != 5 else r.uniform(0, 1)
    tmax = float("inf") if k != 7 else r.uniform(0, hi - lo)
    if nan:
        d[i % 3] = float("nan")
    rows.append(struct.pack("<8f", *o, tmin, *d, tmax))
hdr = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, 8), }" % n
pad = 64 - (10 + len(hdr) + 1) % 64
hdr = hdr + " " * pad + "\n"
with open(out, "wb") as f:
    f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(hdr)) + hdr.encode())
    f.write(b"".join(rows))
