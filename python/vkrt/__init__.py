"""vkrt from Python: render, trace and compare BVH layouts with numpy in and out.

vkrt is a GPU-agnostic ray and path tracer written as Vulkan compute shaders; it runs on any
Vulkan 1.2 device, and on Mesa's lavapipe on a machine without a GPU. This package is a second
front end beside the ``vkrt`` command line, on the same library: the same scene files and
options, the same images (byte for byte), the same hits.

    >>> import vkrt
    >>> scene = vkrt.load_scene("scenes/cornell/cornell-measured.obj")
    >>> image = vkrt.render(scene, spp=64, width=256, height=256)   # (256, 256, 3) float32
    >>> hits = scene.trace(origins, directions)                     # dict of numpy arrays

The GIL is released while the device works; Ctrl-C stops a render with ``KeyboardInterrupt``;
bad input raises ``ValueError`` or ``FileNotFoundError`` with the command line's message.
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _vkrt
from ._vkrt import Progressive, Scene

__all__ = ["Scene", "Progressive", "load_scene", "render", "resume", "merge", "write_image", "devices", "BUILDERS", "LAYOUTS", "__version__"]
__version__: str = _vkrt.__version__

#: BVH builders (``builder=``), as ``vkrt render --builder`` names them.
BUILDERS = ("median", "sah", "sweep-sah", "reinsertion")
#: Stackless BVH layouts (``layout=``), as ``vkrt trace --layout`` names them.
LAYOUTS = ("threaded", "parent-link", "multi-order", "compact", "wide")

PathLike = Union[str, "os.PathLike[str]"]
Vec3 = Sequence[float]
Progress = Union[bool, Callable[[Dict[str, Any]], None], None]


def _vec(name: str, v: Optional[Vec3]) -> Optional[List[float]]:
    if v is None:
        return None
    a = np.asarray(v, dtype=np.float64).ravel()
    if a.shape != (3,):
        raise ValueError(f"{name}={v!r}: expected three numbers x, y, z")
    return [float(x) for x in a]


def _path(name: str, p: Optional[PathLike]) -> Optional[str]:
    if p is None:
        return None
    if not isinstance(p, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path (str or os.PathLike), not {type(p).__name__}")
    return os.fspath(p)


def _warn(scene: Scene) -> Scene:
    for w in scene.warnings:
        warnings.warn(w, stacklevel=3)
    return scene


def _view(
    camera: Optional[int] = None,
    eye: Optional[Vec3] = None,
    target: Optional[Vec3] = None,
    up: Optional[Vec3] = None,
    fov: Optional[float] = None,
    sky: Optional[Vec3] = None,
    envmap: Optional[PathLike] = None,
    envmap_scale: Optional[float] = None,
    envmap_rotate: Optional[float] = None,
) -> Dict[str, Any]:
    """The camera and sky options, checked and converted, as the compiled module takes them."""
    number = lambda x: None if x is None else float(x)  # noqa: E731
    return {
        "camera": camera,
        "eye": _vec("eye", eye),
        "target": _vec("target", target),
        "up": _vec("up", up),
        "fov": number(fov),
        "sky": _vec("sky", sky),
        "envmap": _path("envmap", envmap),
        "envmap_scale": number(envmap_scale),
        "envmap_rotate": number(envmap_rotate),
    }


def devices() -> List[Dict[str, Any]]:
    """Every Vulkan device, as ``vkrt info`` lists them.

    Each is a dict: ``index``, ``name``, ``type``, ``driver``, ``usable``, ``default`` (the one
    used when no ``device=`` is given: ``VKRT_DEVICE``, else a discrete GPU, else the best other
    device, lavapipe on a machine without a GPU) and the limits vkrt reads. Pass an index or
    part of a name as ``device=`` to ``load_scene``.
    """
    return _vkrt.devices()


def load_scene(
    path: PathLike,
    *,
    camera: Optional[int] = None,
    eye: Optional[Vec3] = None,
    target: Optional[Vec3] = None,
    up: Optional[Vec3] = None,
    fov: Optional[float] = None,
    sky: Optional[Vec3] = None,
    envmap: Optional[PathLike] = None,
    envmap_scale: Optional[float] = None,
    envmap_rotate: Optional[float] = None,
    builder: Optional[str] = None,
    layout: Optional[str] = None,
    triangle_list: bool = True,
    device: Optional[Union[int, str]] = None,
) -> Scene:
    """Load a scene file and make it ready to render and trace on a device.

    Takes what ``vkrt render`` takes: a Wavefront ``.obj`` (with its ``.mtl``), a course-lab
    ``.yaml`` or glTF 2.0 (``.gltf``, ``.glb``), and the same options:

    - ``camera``: the file's camera N (0 is the first); ``eye``, ``target``, ``up`` (x, y, z)
      and ``fov`` (vertical, degrees) replace parts of it.
    - ``sky``: linear RGB radiance that escaping rays see, replacing the scene's sky (it lights
      the scene in the path tracer); ``envmap``: an equirectangular ``.hdr`` or ``.exr`` map
      that lights the scene instead, with ``envmap_scale`` and ``envmap_rotate`` (degrees about
      +y).
    - ``builder``: one of ``BUILDERS`` (default ``"reinsertion"``); ``layout``: one of
      ``LAYOUTS`` (default ``"threaded"`` for renders; ``trace`` then walks ``vkrt trace``'s
      default: multi-order, or wide levels for a scene with instances). Neither changes an
      image.
    - ``device``: an index from ``devices()`` or part of a device's name.

    The prepared scene (BVH, shading arrays) is kept in the user's cache folder as the command
    line does, so loading a big scene again is fast. Loader warnings are given to ``warnings``.
    Raises ``FileNotFoundError`` for a missing file, ``ValueError`` for a bad one (naming the
    file and line or field).
    """
    p = _path("path", path)
    if p is None:
        raise TypeError("load_scene() needs a path")
    view = _view(camera, eye, target, up, fov, sky, envmap, envmap_scale, envmap_rotate)
    device = None if device is None else str(device)
    scene = _vkrt._load_scene(p, view, builder=builder, layout=layout, triangle_list=bool(triangle_list), device=device)
    return _warn(scene)


def _array(name: str, a: Any, dtype: Any, columns: Optional[int]) -> np.ndarray:
    """``a`` as a numpy array of ``dtype`` and shape (N, columns), without a copy when it
    already is one (any strides: the library reads them)."""
    arr = np.asarray(a)
    if arr.dtype != dtype:
        if np.issubdtype(dtype, np.integer) and not np.issubdtype(arr.dtype, np.integer):
            raise TypeError(f"{name} must be integers ({np.dtype(dtype).name}), not {arr.dtype}")
        if not np.can_cast(arr.dtype, dtype, casting="same_kind"):
            raise TypeError(f"{name} must be {np.dtype(dtype).name}, not {arr.dtype}")
        if np.issubdtype(dtype, np.integer) and arr.size and (arr.min() < 0 or arr.max() > np.iinfo(dtype).max):
            raise ValueError(f"{name} has values outside {np.dtype(dtype).name}")
        arr = arr.astype(dtype)
    if columns is not None and (arr.ndim != 2 or arr.shape[1] != columns):
        raise ValueError(f"{name} must have shape (N, {columns}), not {arr.shape}")
    if columns is None and arr.ndim != 1:
        raise ValueError(f"{name} must have shape (N,), not {arr.shape}")
    return arr


def _from_arrays(
    vertices: Any,
    triangles: Any,
    material_ids: Any = None,
    materials: Optional[Iterable[Dict[str, Any]]] = None,
    lights: Optional[Iterable[Dict[str, Any]]] = None,
    *,
    normals: Any = None,
    uvs: Any = None,
    eye: Optional[Vec3] = None,
    target: Optional[Vec3] = None,
    up: Optional[Vec3] = None,
    fov: Optional[float] = None,
    sky: Optional[Vec3] = None,
    envmap: Optional[PathLike] = None,
    builder: Optional[str] = None,
    layout: Optional[str] = None,
    device: Optional[Union[int, str]] = None,
) -> Scene:
    """Make a scene from numpy arrays, without files.

    - ``vertices``: (N, 3) float32 positions; ``triangles``: (M, 3) uint32 vertex indices,
      counter-clockwise seen from the front; ``normals`` (N, 3) and ``uvs`` (N, 2) optional.
    - ``material_ids``: (M,) uint32, each triangle's index into ``materials`` (default all 0).
    - ``materials``: dicts with MTL's parameters ``diffuse``, ``specular``, ``shininess``,
      ``emission`` (an emitter: an area light), ``ior``, ``illum`` (3 mirror, 7 glass), or
      glTF's ``metallic`` and ``roughness``; default one grey diffuse material.
    - ``lights``: dicts ``{"type": "point", "position": ..., "intensity": ...}`` or
      ``{"type": "directional", "direction": ..., "intensity": ...}``. A scene with neither
      lights nor emitters gets vkrt's default light, as an unlit file does.
    - the camera (default: vkrt's, framing the scene) and sky as in ``load_scene``.

    Triangle ``i`` is hit ``prim`` ``i`` in ``trace``, unless degenerate triangles (zero area)
    were dropped before it.
    """
    v = _array("vertices", vertices, np.float32, 3)
    t = _array("triangles", triangles, np.uint32, 3)
    ids = None if material_ids is None else _array("material_ids", material_ids, np.uint32, None)
    n = None if normals is None else _array("normals", normals, np.float32, 3)
    uv = None if uvs is None else _array("uvs", uvs, np.float32, 2)
    scene = _vkrt._scene_from_arrays(
        v,
        t,
        ids,
        None if materials is None else [dict(m) for m in materials],
        None if lights is None else [dict(li) for li in lights],
        n,
        uv,
        _view(eye=eye, target=target, up=up, fov=fov, sky=sky, envmap=envmap),
        builder=builder,
        layout=layout,
        device=None if device is None else str(device),
    )
    return _warn(scene)


#: A hit as the device writes it (``GpuHit``, 32 bytes): ``trace``'s arrays are views of these
#: fields, so the hits are never copied after the device's read-back.
_HIT_DTYPE = np.dtype(
    [("t", "<f4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4"), ("nodes", "<u4"), ("triangles", "<u4"), ("_pad", "<u4", (2,))]
)


def _hits(words: np.ndarray) -> Dict[str, np.ndarray]:
    records = words.view(_HIT_DTYPE).reshape(-1)
    return {name: records[name] for name in ("t", "prim", "u", "v", "nodes", "triangles")}


def _trace(
    self: Scene,
    origins: Any,
    directions: Any = None,
    tmin: Union[float, Any] = 0.0,
    tmax: Union[float, Any] = np.inf,
    any_hit: bool = False,
    layout: Optional[str] = None,
) -> Dict[str, np.ndarray]:
    """Trace rays: closest hits (or, with ``any_hit``, whether anything is hit).

    ``origins`` and ``directions`` are (N, 3) float32 arrays (read in place, whatever their
    strides); ``tmin`` and ``tmax`` a number or (N,) each. Or give one (N, 8) float32 array
    in ``vkrt trace``'s layout (origin, tmin, direction, tmax: what ``vkrt rays`` writes) as
    ``origins`` alone: read in place, without a copy, when it is C-contiguous. Directions need
    not be unit length: ``t`` is in units of the direction. Returns a dict of (N,) arrays, as
    ``vkrt trace`` writes them: ``t`` (float32, +inf on a miss), ``prim`` (uint32 triangle
    index, 0xFFFFFFFF on a miss), ``u``, ``v`` (barycentrics of the second and third vertex),
    and the traversal counters ``nodes`` (boxes tested) and ``triangles`` (triangles tested);
    they are views of one record array (strided), made without a copy.

    ``layout``: the BVH layout to walk (``LAYOUTS``); default the scene's if ``load_scene`` was
    given one, else ``vkrt trace``'s default (copies of a mesh, the lab YAML's ``Instances``
    or a glTF mesh placed more than once, are walked through their two-level BVH, both levels
    in the layout). The same bits as ``vkrt trace`` for every builder and
    layout. Raises ``ValueError`` for wrong shapes and non-finite or zero rays.
    """
    if directions is None:
        if np.ndim(origins) == 2 and np.shape(origins)[1] == 3:
            raise ValueError("trace() needs directions beside (N, 3) origins, or one (N, 8) array of rays")
        rays = _array("rays", origins, np.float32, 8)
        return _hits(self._trace_packed(rays, any_hit=bool(any_hit), layout=layout))
    o = _array("origins", origins, np.float32, 3)
    d = _array("directions", directions, np.float32, 3)
    if o.shape != d.shape:
        raise ValueError(f"origins {o.shape} and directions {d.shape} must have the same shape")
    count = o.shape[0]
    lo = np.broadcast_to(np.asarray(tmin, dtype=np.float32), (count,))
    hi = np.broadcast_to(np.asarray(tmax, dtype=np.float32), (count,))
    return _hits(self._trace(o, d, lo, hi, any_hit=bool(any_hit), layout=layout))


def _bvh_stats(
    self: Scene,
    builders: Optional[Sequence[str]] = None,
    layouts: Optional[Sequence[str]] = None,
    width: int = 384,
    height: int = 384,
    repeat: int = 3,
) -> Dict[str, list]:
    """What ``vkrt bvh`` measures for this scene, one row per builder x layout, as a dict of
    columns that ``pandas.DataFrame`` takes: build time, nodes, bytes, SAH cost, and for
    primary, shadow and diffuse-bounce rays from this scene's camera the nodes visited and
    triangles tested per ray (the device's counters) and rays per second. ``builders`` and
    ``layouts`` limit the table (default all); ``width`` x ``height`` primary rays; the best of
    ``repeat`` builds is timed.
    """
    return self._bvh_stats(
        builders=None if builders is None else list(builders),
        layouts=None if layouts is None else list(layouts),
        width=int(width),
        height=int(height),
        repeat=int(repeat),
    )


Scene.from_arrays = staticmethod(_from_arrays)  # type: ignore[attr-defined]
Scene.trace = _trace  # type: ignore[attr-defined]
Scene.bvh_stats = _bvh_stats  # type: ignore[attr-defined]


def render(
    scene: Scene,
    spp: Optional[int] = None,
    integrator: str = "path",
    *,
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: int = 0,
    max_depth: Optional[int] = None,
    seconds: Optional[float] = None,
    target_relmse: Optional[float] = None,
    progress: Progress = True,
) -> np.ndarray:
    """Render ``scene``; returns linear radiance, a (height, width, 3) float32 array.

    The same bytes as ``vkrt render`` writes to a ``.pfm`` for the same settings.

    - ``integrator``: ``"path"`` (progressive, unbiased) or ``"whitted"``.
    - ``spp``: samples per pixel (path: default 16 unless ``seconds`` or ``target_relmse``;
      Whitted: default 1, the pixel centre). ``seconds`` and ``target_relmse`` stop a path
      tracer's run at a time or an estimated error, the first rule to hold.
    - ``width``, ``height``: default 512; ``seed``: the same seed gives the same image.
    - ``max_depth``: rays per path (Whitted default 7, at most 15; path default unbounded).
    - ``progress``: ``True`` shows vkrt's bar on stderr, ``False`` nothing, a callable is
      called with a dict (``spp``, ``fraction``, ``seconds``, ``relmse``, ...) between batches.

    For more control (add samples, read the error estimate, checkpoints), use ``Progressive``.
    """
    return _vkrt._render(
        scene,
        spp=None if spp is None else int(spp),
        integrator=integrator,
        width=None if width is None else int(width),
        height=None if height is None else int(height),
        seed=int(seed),
        max_depth=None if max_depth is None else int(max_depth),
        seconds=None if seconds is None else float(seconds),
        target_relmse=None if target_relmse is None else float(target_relmse),
        progress=progress,
    )


def resume(checkpoint: PathLike, device: Optional[Union[int, str]] = None) -> Progressive:
    """Continue a run saved by ``Progressive.save`` or ``vkrt render --checkpoint``.

    The scene is loaded as the run had it (its file, sky, camera, builder and layout); the
    scene's files must be unchanged (their content hashes are checked). Add samples with
    ``add``; the result is the same bytes as the run done in one go.
    """
    p = _path("checkpoint", checkpoint)
    if p is None:
        raise TypeError("resume() needs a checkpoint path")
    return _vkrt._resume(p, device=None if device is None else str(device))


def merge(checkpoints: Sequence[PathLike], output: Optional[PathLike] = None) -> np.ndarray:
    """Add checkpoints of runs with different seeds, or every shard of one sharded run
    (``vkrt render --shard``), as ``vkrt merge`` does; returns the merged image and writes
    ``output`` if given (an image, or a ``.ckpt`` to merge or resume again)."""
    paths = [_path("checkpoints", c) for c in checkpoints]
    return _vkrt._merge([p for p in paths if p is not None], output=_path("output", output))


def write_image(path: PathLike, image: Any, exposure: Union[float, str, None] = None, tonemap: Optional[str] = None) -> None:
    """Write a (height, width, 3) linear image as ``vkrt render`` writes its output, atomically.

    The extension picks the format: ``.png`` (8-bit sRGB after ``exposure`` in stops or
    ``"auto"``, the default, and ``tonemap``: ``"neutral"`` (default), ``"aces"`` or
    ``"clamp"``), ``.exr`` or ``.pfm`` (linear float32, as given). For an image from
    ``render`` the bytes are the command line's for the same settings.
    """
    p = _path("path", path)
    if p is None:
        raise TypeError("write_image() needs a path")
    arr = np.asarray(image)
    if arr.dtype != np.float32:
        if not np.issubdtype(arr.dtype, np.floating):
            raise TypeError(f"image must be float32 radiance, not {arr.dtype}")
        arr = arr.astype(np.float32)
    ev = None if exposure is None else str(exposure)
    _vkrt._write_image(p, arr, exposure=ev, tonemap=tonemap)
