"""Bad input raises ValueError, TypeError or FileNotFoundError with the command line's message,
never a crash; scenes from arrays; devices; the GIL and Ctrl-C."""

import _thread
import signal
import threading
import time

import numpy as np
import pytest
import vkrt


def test_missing_and_bad_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="nothing.obj"):
        vkrt.load_scene(tmp_path / "nothing.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(ValueError, match=r"bad\.obj"):
        vkrt.load_scene(bad)
    (tmp_path / "scene.txt").write_text("not a scene")
    with pytest.raises(ValueError, match=r"scene\.txt"):
        vkrt.load_scene(tmp_path / "scene.txt")


def test_bad_options(cornell):
    with pytest.raises(ValueError, match="builder"):
        vkrt.load_scene(cornell, builder="octree")
    with pytest.raises(ValueError, match="eye"):
        vkrt.load_scene(cornell, eye=(1, 2))
    with pytest.raises(ValueError, match="fov"):
        vkrt.load_scene(cornell, fov=0)
    scene = vkrt.load_scene(cornell)
    with pytest.raises(ValueError, match="integrator"):
        vkrt.render(scene, integrator="photon")
    with pytest.raises(ValueError, match="max_depth"):
        vkrt.render(scene, integrator="whitted", max_depth=99)


def test_absurd_sizes_are_refused_before_any_work(cornell):
    scene = vkrt.load_scene(cornell)
    with pytest.raises(ValueError, match="pixels"):
        vkrt.render(scene, width=1_000_000, height=1_000_000)
    with pytest.raises(ValueError, match="width"):
        vkrt.render(scene, width=0)
    with pytest.raises(OverflowError):
        vkrt.render(scene, width=-3)


def test_bad_ray_arrays(cornell):
    scene = vkrt.load_scene(cornell)
    o = np.zeros((4, 3), np.float32)
    d = np.ones((4, 3), np.float32)
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        scene.trace(o[:, :2], d[:, :2])
    with pytest.raises(ValueError, match="needs directions"):
        scene.trace(o)
    with pytest.raises(ValueError, match="same shape"):
        scene.trace(o, d[:3])
    with pytest.raises(TypeError, match="float32"):
        scene.trace(o.astype(np.complex64), d)
    nan = d.copy()
    nan[2, 1] = np.nan
    with pytest.raises(ValueError, match="ray 2"):
        scene.trace(o, nan)
    with pytest.raises(ValueError, match="ray 0: the direction is zero"):
        scene.trace(o, np.zeros((4, 3), np.float32))
    with pytest.raises(ValueError, match="tmin"):
        scene.trace(o, d, tmin=-1.0)
    empty = scene.trace(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32))
    assert all(len(v) == 0 for v in empty.values())


def test_scene_from_arrays_traces_and_renders():
    # A floor (two triangles) under a point light, one emissive-free material per triangle.
    vertices = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], np.float32)
    triangles = np.array([[0, 2, 1], [0, 3, 2]], np.uint32)
    materials = [{"diffuse": (0.8, 0.2, 0.2)}, {"diffuse": (0.2, 0.8, 0.2)}]
    lights = [{"type": "point", "position": (0, 2, 0), "intensity": (4, 4, 4)}]
    scene = vkrt.Scene.from_arrays(vertices, triangles, np.array([0, 1], np.uint32), materials, lights, eye=(0, 2, 2), target=(0, 0, 0))
    assert scene.triangle_count == 2 and scene.path is None
    hits = scene.trace(np.array([[0.5, 1, -0.2], [-0.5, 1, 0.5], [3, 1, 0]], np.float32), np.array([[0, -1, 0]] * 3, np.float32))
    np.testing.assert_array_equal(hits["prim"], [0, 1, 0xFFFFFFFF])
    np.testing.assert_allclose(hits["t"][:2], [1.0, 1.0])
    image = vkrt.render(scene, spp=4, width=16, height=16, progress=False)
    centre = image[8, 8]
    assert image.max() > 0 and centre.sum() > 0
    with pytest.raises(ValueError, match="names vertex 7"):
        vkrt.Scene.from_arrays(vertices, np.array([[0, 1, 7]], np.uint32))
    with pytest.raises(ValueError, match="material_ids"):
        vkrt.Scene.from_arrays(vertices, triangles, np.array([0, 5], np.uint32), materials)
    with pytest.raises(ValueError, match="vertices"):
        vkrt.Scene.from_arrays(np.full((4, 3), np.nan, np.float32), triangles)
    with pytest.raises(ValueError, match="unknown key"):
        vkrt.Scene.from_arrays(vertices, triangles, materials=[{"colour": (1, 1, 1)}])
    with pytest.raises(ValueError, match="no triangles"):
        vkrt.Scene.from_arrays(np.zeros((3, 3), np.float32), np.array([[0, 1, 2]], np.uint32))
    with pytest.raises(ValueError, match="arrays"):
        run = vkrt.Progressive(scene, spp=2, width=8, height=8)
        run.save("/tmp/never.ckpt")


def test_devices_name_the_default(cornell):
    devices = vkrt.devices()
    assert devices and sum(d["default"] for d in devices) == 1
    assert all(d["name"] and d["max_texel_buffer_elements"] > 0 for d in devices)
    with pytest.raises(ValueError, match="no-such-device"):
        vkrt.load_scene(cornell, device="no-such-device")


def test_the_gil_is_released_while_rendering(cornell):
    scene = vkrt.load_scene(cornell)
    vkrt.render(scene, spp=1, width=8, height=8, progress=False)  # pipelines warm
    done = threading.Event()

    def work():
        vkrt.render(scene, spp=512, width=128, height=128, progress=False)
        done.set()

    t = threading.Thread(target=work)
    start = time.perf_counter()
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    # Holding the GIL, the render would leave this thread no turn for its whole length (a tick
    # or two at most); released, it ticks every millisecond or so (fewer on a loaded machine).
    assert elapsed > 0.2 and ticks >= 50, (ticks, elapsed)


def test_ctrl_c_stops_a_long_render(cornell):
    scene = vkrt.load_scene(cornell)
    run = vkrt.Progressive(scene, width=64, height=64)
    # Python's own Ctrl-C handler, as an interactive session has it: a process started in the
    # background by a shell (CI's runner) inherits SIGINT ignored, and then Python installs none
    # and interrupt_main does nothing.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(1.0, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            run.add(seconds=120, progress=False)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.perf_counter() - start < 30
    assert run.spp > 0, "the samples finished before Ctrl-C are kept"


def test_help_shows_docstrings_and_hints():
    assert "spp" in vkrt.render.__doc__ and "float32" in vkrt.render.__doc__
    assert "layout" in vkrt.Scene.trace.__doc__
    assert vkrt.render.__annotations__["return"] in ("np.ndarray", np.ndarray)
    assert "Progressive" in vkrt.Progressive.__doc__ or "progressive" in vkrt.Progressive.__doc__
