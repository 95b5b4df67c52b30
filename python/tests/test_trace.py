"""`Scene.trace` gives `vkrt trace`'s hits bit for bit, for every builder and layout."""

import numpy as np
import pytest
import vkrt
from conftest import ROOT


def random_rays(scene, n, seed):
    """Rays from inside the scene's camera neighbourhood in every direction (incoherent)."""
    rng = np.random.default_rng(seed)
    eye = np.array(scene.camera["eye"], np.float32)
    target = np.array(scene.camera["target"], np.float32)
    origins = (eye + (target - eye) * rng.uniform(0.2, 1.0, (n, 1))).astype(np.float32)
    directions = rng.normal(size=(n, 3)).astype(np.float32)
    return origins, directions


def write_npy_rays(path, origins, directions, tmin, tmax):
    rays = np.zeros((len(origins), 8), np.float32)
    rays[:, 0:3], rays[:, 3], rays[:, 4:7], rays[:, 7] = origins, tmin, directions, tmax
    np.save(path, rays)


@pytest.mark.parametrize("layout", vkrt.LAYOUTS)
def test_hits_equal_vkrt_trace_for_each_layout(cli, cornell, tmp_path, layout):
    scene = vkrt.load_scene(cornell, layout=layout)
    origins, directions = random_rays(scene, 3000, 7)
    hits = scene.trace(origins, directions, tmin=0.0, tmax=np.inf)
    write_npy_rays(tmp_path / "rays.npy", origins, directions, 0.0, np.inf)
    cli("trace", cornell, "--rays", tmp_path / "rays.npy", "--layout", layout, "-o", tmp_path / "hits.npy")
    expected = np.load(tmp_path / "hits.npy")
    for key in ("t", "prim", "u", "v"):
        np.testing.assert_array_equal(hits[key], expected[key], err_msg=f"{layout}: {key}")
    hit = hits["prim"] != 0xFFFFFFFF
    assert 0.1 < hit.mean() < 0.9, "rays from in front of the open box hit it or miss it"
    assert np.all(np.isinf(hits["t"][~hit]))
    assert np.all(hits["nodes"] >= 1)


@pytest.mark.parametrize("builder", vkrt.BUILDERS)
def test_hits_equal_vkrt_trace_for_each_builder_on_a_bigger_scene(cli, tmp_path, builder):
    gltf = ROOT / "scenes" / "gltf" / "showcase.gltf"
    scene = vkrt.load_scene(gltf, builder=builder, layout="multi-order")
    origins, directions = random_rays(scene, 2000, 3)
    hits = scene.trace(origins, directions, tmax=50.0)
    write_npy_rays(tmp_path / "rays.npy", origins, directions, 0.0, 50.0)
    cli("trace", gltf, "--rays", tmp_path / "rays.npy", "--builder", builder, "--layout", "multi-order", "-o", tmp_path / "hits.npy")
    expected = np.load(tmp_path / "hits.npy")
    for key in ("t", "prim", "u", "v"):
        np.testing.assert_array_equal(hits[key], expected[key], err_msg=f"{builder}: {key}")


def test_default_layout_is_vkrt_traces_and_strides_do_not_matter(cli, cornell, tmp_path):
    scene = vkrt.load_scene(cornell)
    origins, directions = random_rays(scene, 500, 11)
    hits = scene.trace(origins, directions)
    write_npy_rays(tmp_path / "rays.npy", origins, directions, 0.0, np.inf)
    cli("trace", cornell, "--rays", tmp_path / "rays.npy", "-o", tmp_path / "hits.npy")
    np.testing.assert_array_equal(hits["t"], np.load(tmp_path / "hits.npy")["t"])
    # Every other row of a bigger array (non-contiguous), and float64 input: the same hits.
    wide = np.zeros((1000, 3), np.float32)
    wide[::2] = directions
    strided = scene.trace(origins.astype(np.float64), wide[::2])
    for key in hits:
        np.testing.assert_array_equal(strided[key], hits[key])
    # The (N, 8) array vkrt rays writes, in place; and a non-contiguous one.
    packed = np.load(tmp_path / "rays.npy")
    for rays in (packed, np.repeat(packed, 2, axis=0)[::2]):
        again = scene.trace(rays)
        for key in hits:
            np.testing.assert_array_equal(again[key], hits[key])
    packed[3, 5] = np.nan
    with pytest.raises(ValueError, match="ray 3"):
        scene.trace(packed)
    with pytest.raises(ValueError, match=r"\(N, 8\)"):
        scene.trace(packed[:, :7])


def test_any_hit_agrees_with_closest_hit(cornell):
    scene = vkrt.load_scene(cornell)
    origins, directions = random_rays(scene, 1000, 5)
    closest = scene.trace(origins, directions, tmax=100.0)
    anyhit = scene.trace(origins, directions, tmax=100.0, any_hit=True)
    np.testing.assert_array_equal(anyhit["prim"] != 0xFFFFFFFF, closest["prim"] != 0xFFFFFFFF)
    assert anyhit["nodes"].sum() <= closest["nodes"].sum()


def test_per_ray_tmin_and_tmax(cornell):
    scene = vkrt.load_scene(cornell)
    origins, directions = random_rays(scene, 200, 9)
    full = scene.trace(origins, directions)
    short = scene.trace(origins, directions, tmax=full["t"] * 0.5)
    assert np.all(short["prim"] == 0xFFFFFFFF), "nothing is closer than the closest hit"


def test_bvh_stats_is_a_table_of_builders_by_layouts(cornell):
    scene = vkrt.load_scene(cornell)
    stats = scene.bvh_stats(builders=["sah", "median"], layouts=["threaded", "wide"], width=32, height=32, repeat=1)
    lengths = {len(v) for v in stats.values()}
    assert lengths == {4}
    assert set(stats["builder"]) == {"sah", "median"} and set(stats["layout"]) == {"threaded", "wide"}
    assert all(n > 0 for n in stats["primary_nodes_per_ray"])
    assert all(r > 0 for r in stats["diffuse_rays_per_second"])
    with pytest.raises(ValueError, match="layout"):
        scene.bvh_stats(layouts=["spiral"])


def test_an_instanced_scene_traces_its_two_level_bvh_by_default_as_vkrt_trace(cli, tmp_path):
    """Copies of a mesh (the lab YAML's `Instances`) are walked through the two-level BVH by
    default, as `vkrt trace` walks them: the same hits bit for bit, and where the copies are:
    each ray straight down hits where it falls inside a copy (a point-in-triangle test of its
    own here), and the same hits in another layout's levels."""
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    transforms = "".join(f"      - {{Translation: [{2 * x}, {2 * y}, 0], Rotation: [0, 0, {10 * x}]}}\n" for x in range(4) for y in range(4))
    yaml = f"Materials:\n  - Name: m\nInstances:\n  - Mesh: tri.obj\n    Material: m\n    Transforms:\n{transforms}"
    path = tmp_path / "copies.yaml"
    path.write_text(yaml)
    scene = vkrt.load_scene(path)
    rng = np.random.default_rng(5)
    origins = np.column_stack([rng.uniform(-0.5, 8.0, 2000), rng.uniform(-0.5, 8.0, 2000), np.full(2000, 5.0)]).astype(np.float32)
    directions = np.tile(np.array([0.0, 0.0, -1.0], np.float32), (2000, 1))
    hits = scene.trace(origins, directions)
    write_npy_rays(tmp_path / "rays.npy", origins, directions, 0.0, np.inf)
    cli("trace", path, "--rays", tmp_path / "rays.npy", "-o", tmp_path / "hits.npy")
    expected = np.load(tmp_path / "hits.npy")
    for key in ("t", "prim", "u", "v"):
        np.testing.assert_array_equal(hits[key], expected[key], err_msg=key)
    placed = scene.trace(origins, directions, layout="compact")
    np.testing.assert_array_equal(hits["t"], placed["t"])
    hit = hits["prim"] != 0xFFFFFFFF
    assert 0.1 < hit.mean() < 0.9
    # Copy (x, y): the triangle (0,0) (1,0) (0,1) turned 10x degrees about z, moved to (2x, 2y).
    inside = np.zeros(len(origins), bool)
    for x in range(4):
        for y in range(4):
            a = np.radians(10 * x)
            px, py = origins[:, 0] - 2 * x, origins[:, 1] - 2 * y
            lx, ly = np.cos(a) * px + np.sin(a) * py, -np.sin(a) * px + np.cos(a) * py
            inside |= (lx >= 0) & (ly >= 0) & (lx + ly <= 1)
    # The turned copies' edges round differently in object space: a ray may graze past one.
    assert (hit == inside).mean() >= 0.995
    np.testing.assert_allclose(hits["t"][hit], 5.0, rtol=1e-5)
