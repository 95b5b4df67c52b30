"""Shared fixtures: the repository's scenes, the `vkrt` command line to compare against, and a
reader for the `.pfm` images it writes."""

import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def vkrt_bin() -> str:
    """The command line: $VKRT_BIN (tools/test sets it to the binary it built), else a build in
    target/, else `vkrt` on PATH."""
    if os.environ.get("VKRT_BIN"):
        return os.environ["VKRT_BIN"]
    for profile in ("release", "debug"):
        p = ROOT / "target" / profile / "vkrt"
        if p.exists():
            return str(p)
    found = shutil.which("vkrt")
    if found is None:
        pytest.fail("no vkrt binary: build it (cargo build --release) or set VKRT_BIN")
    return found


@pytest.fixture(scope="session")
def cli():
    """Runs `vkrt ARGS...`, failing the test with its stderr if it fails."""

    def run(*args, ok=True):
        r = subprocess.run([vkrt_bin(), *map(str, args)], capture_output=True, text=True)
        if ok and r.returncode != 0:
            pytest.fail(f"vkrt {' '.join(map(str, args))} failed ({r.returncode}):\n{r.stderr}")
        return r

    return run


def read_pfm(path) -> np.ndarray:
    """A colour PFM as (height, width, 3) float32, top row first (the file stores the bottom row
    first; a negative scale means little-endian)."""
    data = pathlib.Path(path).read_bytes()
    parts = data.split(b"\n", 3)
    assert parts[0] == b"PF", f"{path}: not a colour PFM"
    width, height = map(int, parts[1].split())
    scale = float(parts[2])
    dtype = "<f4" if scale < 0 else ">f4"
    pixels = np.frombuffer(parts[3], dtype=dtype, count=width * height * 3).reshape(height, width, 3)
    return pixels[::-1].astype(np.float32)


@pytest.fixture(scope="session")
def scenes():
    return ROOT / "scenes"


@pytest.fixture(scope="session")
def cornell(scenes):
    return scenes / "cornell-measured" / "cornell.yaml"


@pytest.fixture(scope="session")
def lab_box(scenes):
    return scenes / "lab" / "cornell_box" / "cornell_box.yaml"
