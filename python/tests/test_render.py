"""Renders through Python give the command line's bytes; progressive runs, checkpoints (made in
Python, resumed by the command line and back) and merges agree with it too."""

import numpy as np
import pytest
import vkrt
from conftest import ROOT, read_pfm


def test_path_render_is_the_clis_pfm(cli, cornell, tmp_path):
    scene = vkrt.load_scene(cornell)
    image = vkrt.render(scene, spp=8, width=48, height=40, seed=3, progress=False)
    assert image.shape == (40, 48, 3) and image.dtype == np.float32
    out = tmp_path / "cli.pfm"
    cli("render", cornell, "--integrator", "path", "--spp", 8, "--width", 48, "--height", 40, "--seed", 3, "-o", out, "-q")
    expected = read_pfm(out)
    assert image.mean() > 0.01, "a lit box renders light"
    np.testing.assert_array_equal(image, expected)


def test_whitted_render_with_camera_overrides_is_the_clis_pfm(cli, lab_box, tmp_path):
    eye, target = (300.0, 250.0, -700.0), (270.0, 280.0, 0.0)
    scene = vkrt.load_scene(lab_box, eye=eye, target=target, fov=45)
    image = vkrt.render(scene, integrator="whitted", spp=2, width=40, height=32, progress=False)
    out = tmp_path / "cli.pfm"
    cli("render", lab_box, "--eye", "300,250,-700", "--target", "270,280,0", "--fov", 45, "--spp", 2, "--width", 40, "--height", 32, "-o", out, "-q")
    np.testing.assert_array_equal(image, read_pfm(out))
    default = vkrt.render(vkrt.load_scene(lab_box), integrator="whitted", width=40, height=32, progress=False)
    assert not np.array_equal(default, image), "the camera options change the image"


def test_envmap_render_is_the_clis_pfm(cli, scenes, tmp_path):
    obj, env = scenes / "envmap" / "envmap-scene.obj", ROOT / "tests" / "refs" / "envmap-sun.exr"
    scene = vkrt.load_scene(obj, envmap=env, envmap_rotate=30)
    image = vkrt.render(scene, spp=4, width=32, height=32, progress=False)
    out = tmp_path / "cli.pfm"
    cli("render", obj, "--integrator", "path", "--envmap", env, "--envmap-rotate", 30, "--spp", 4, "--width", 32, "--height", 32, "-o", out, "-q")
    np.testing.assert_array_equal(image, read_pfm(out))


def test_progressive_steps_make_the_one_run_image(cornell):
    scene = vkrt.load_scene(cornell)
    run = vkrt.Progressive(scene, spp=8, width=32, height=24, seed=1)
    assert run.spp == 0 and run.relmse is None
    run.add(3, progress=False)
    assert run.spp == 3
    run.add(5, progress=False)
    assert run.spp == 8 and run.relmse is not None and run.relmse > 0
    whole = vkrt.render(scene, spp=8, width=32, height=24, seed=1, progress=False)
    np.testing.assert_array_equal(run.image(), whole)


def test_checkpoint_from_python_resumes_in_the_cli_and_back(cli, cornell, tmp_path):
    scene = vkrt.load_scene(cornell)
    run = vkrt.Progressive(scene, spp=8, width=32, height=24, seed=2)
    run.add(4, progress=False)
    ckpt = tmp_path / "run.ckpt"
    run.save(ckpt)
    out = tmp_path / "resumed.pfm"
    cli("render", "--resume", ckpt, "--spp", 8, "-o", out, "-q")
    whole = vkrt.render(scene, spp=8, width=32, height=24, seed=2, progress=False)
    np.testing.assert_array_equal(read_pfm(out), whole)

    # And a CLI checkpoint continued here.
    cli_ckpt = tmp_path / "cli.ckpt"
    cli("render", cornell, "--spp", 4, "--width", 32, "--height", 24, "--seed", 5, "--checkpoint", cli_ckpt, "-o", tmp_path / "four.pfm", "-q")
    back = vkrt.resume(cli_ckpt)
    assert back.spp == 4 and (back.width, back.height, back.seed) == (32, 24, 5)
    back.add(4, progress=False)
    cli("render", "--resume", cli_ckpt, "--spp", 8, "-o", tmp_path / "eight.pfm", "-q")
    np.testing.assert_array_equal(back.image(), read_pfm(tmp_path / "eight.pfm"))


def test_a_checkpoint_of_another_scene_is_refused(cornell, lab_box, tmp_path):
    run = vkrt.Progressive(vkrt.load_scene(cornell), spp=4, width=16, height=16)
    run.add(2, progress=False)
    ckpt = tmp_path / "run.ckpt"
    run.save(ckpt)
    data = bytearray(ckpt.read_bytes())
    (tmp_path / "broken.ckpt").write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(ValueError, match="broken.ckpt"):
        vkrt.resume(tmp_path / "broken.ckpt")
    with pytest.raises(FileNotFoundError):
        vkrt.resume(tmp_path / "missing.ckpt")


def test_merge_of_two_seeds_is_the_clis(cli, cornell, tmp_path):
    scene = vkrt.load_scene(cornell)
    paths = []
    for seed in (1, 2):
        run = vkrt.Progressive(scene, spp=4, width=24, height=24, seed=seed)
        run.add(4, progress=False)
        paths.append(tmp_path / f"s{seed}.ckpt")
        run.save(paths[-1])
    merged = vkrt.merge(paths, output=tmp_path / "py.pfm")
    cli("merge", *paths, "-o", tmp_path / "cli.pfm")
    np.testing.assert_array_equal(merged, read_pfm(tmp_path / "cli.pfm"))
    np.testing.assert_array_equal(read_pfm(tmp_path / "py.pfm"), merged)
    with pytest.raises(ValueError, match="seed"):
        vkrt.merge([paths[0], paths[0]])


def test_progress_callback_sees_the_samples_grow(cornell):
    scene = vkrt.load_scene(cornell)
    seen = []
    vkrt.render(scene, spp=16, width=32, height=32, progress=seen.append)
    assert seen, "the callback ran"
    spp = [s["spp"] for s in seen]
    assert spp == sorted(spp) and spp[-1] == 16
    assert all(0.0 <= s["fraction"] <= 1.0 for s in seen)


def test_an_exception_in_the_callback_stops_the_render_and_is_raised(cornell):
    scene = vkrt.load_scene(cornell)
    run = vkrt.Progressive(scene, spp=4096, width=64, height=64)

    def stop(status):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        run.add(4096, progress=stop)
    assert 0 < run.spp < 4096, "the samples finished before the stop are kept"


def test_write_image_writes_the_clis_files(cli, cornell, tmp_path):
    scene = vkrt.load_scene(cornell)
    image = vkrt.render(scene, spp=4, width=32, height=24, progress=False)
    for name, flags, kwargs in (("a.png", [], {}), ("b.png", ["--exposure", "1.5", "--tonemap", "aces"], {"exposure": 1.5, "tonemap": "aces"}), ("c.pfm", [], {}), ("d.exr", [], {})):
        cli("render", cornell, "--integrator", "path", "--spp", 4, "--width", 32, "--height", 24, "-o", tmp_path / f"cli-{name}", "-q", *flags)
        vkrt.write_image(tmp_path / f"py-{name}", image, **kwargs)
        assert (tmp_path / f"py-{name}").read_bytes() == (tmp_path / f"cli-{name}").read_bytes(), name
    with pytest.raises(ValueError, match="shape"):
        vkrt.write_image(tmp_path / "x.png", image[:, :, :2])
    with pytest.raises(ValueError, match="tonemap"):
        vkrt.write_image(tmp_path / "x.png", image, tonemap="sepia")
    with pytest.raises(ValueError, match="unknown image format"):
        vkrt.write_image(tmp_path / "x.bmp", image)
    assert not (tmp_path / "x.png").exists()
