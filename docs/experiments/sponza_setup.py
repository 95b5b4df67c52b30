"""What the Sponza experiment scripts share (sponza-mean-vs-mitsuba.py, sponza-offset-pairs.py):
the realistic ladder's Sponza, camera and map at 320x240, its 2048-spp reference, the dim-pixel
mask (the reference's luminance 0.01-0.05), an EXR reader and one vkrt path render. Needs the
reference (tools/realistic_ladder.py --scenes sponza --reference-spp 2048), mitsuba and numpy."""
import sys, os, subprocess, numpy as np
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
os.chdir(ROOT)
import realistic_ladder as rl  # noqa: E402
from types import SimpleNamespace  # noqa: E402
from path_time_to_error import vkrt_scene_flags  # noqa: E402
import mitsuba as mi  # noqa: E402

WIDTH, HEIGHT = 320, 240
NAME = "sponza"
SPEC = rl.SCENES[NAME]
OBJ, MTL, _, _ = rl.prepare(NAME, SPEC)
CAMERA = {"eye": SPEC["eye"], "target": SPEC["target"], "up": SPEC["up"], "fov": SPEC["fov"]}
ENVMAP = rl.ENVMAP


def load(path):
    """An EXR (or any image Mitsuba reads) as a float64 RGB array; needs a Mitsuba variant set."""
    return np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32), dtype=np.float64)


def reference_and_dim():
    """The 2048-spp reference and its dim-pixel mask."""
    ref = load(rl.reference_path(NAME, SPEC, OBJ, MTL, WIDTH, HEIGHT, 2048))
    lum = ref @ np.array([0.2126, 0.7152, 0.0722])
    return ref, (lum >= 0.01) & (lum < 0.05)


def render_vkrt(binary, seed, spp, out, extra=()):
    """One vkrt path render of the scene into `out`, read back."""
    cam = vkrt_scene_flags(SimpleNamespace(vkrt_camera=True, envmap=ENVMAP, **CAMERA))
    subprocess.run([binary, "render", OBJ, "--integrator", "path", "--width", str(WIDTH), "--height", str(HEIGHT),
                    "--spp", str(spp), "--seed", str(seed), "-o", out, *cam, *extra], check=True, capture_output=True)
    return load(out)
