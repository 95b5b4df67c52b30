#!/usr/bin/env python3
"""Seeds for the `gltf` fuzz target: every .gltf and .glb tests/gltf.rs wrote under
target/test-output/gltf/ (run `cargo test --test gltf` first) and scenes/gltf/showcase.gltf,
each .gltf with its external buffer renamed `f.bin` and appended after a 0xFF byte, the
target's input format. Usage: python3 fuzz/gltf_seeds.py OUT_DIR (from the repository root)."""
import glob
import os
import re
import sys

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
files = sorted(glob.glob("target/test-output/gltf/**/*.gltf", recursive=True)) + ["scenes/gltf/showcase.gltf"]
seeds = []
for path in files:
    text = open(path, "rb").read().decode()
    data = text.encode()
    bins = re.findall(r'"uri"\s*:\s*"([^"]+\.bin)"', text)
    if bins:
        bin_path = os.path.join(os.path.dirname(path), bins[0])
        if os.path.exists(bin_path):
            data = text.replace(f'"{bins[0]}"', '"f.bin"').encode() + b"\xff" + open(bin_path, "rb").read()
    seeds.append(data)
seeds += [open(p, "rb").read() for p in sorted(glob.glob("target/test-output/gltf/**/*.glb", recursive=True))]
for i, data in enumerate(seeds):
    with open(os.path.join(out, f"seed-{i:02d}"), "wb") as f:
        f.write(data)
print(f"{len(seeds)} seeds in {out}")
