//! `vkrt.Scene`: a scene loaded (or made from arrays), prepared and uploaded to a device once,
//! then rendered, traced and measured as often as asked.
//!
//! Loading follows `vkrt render` step for step (the prepared-scene cache, the sky and
//! environment map, the camera's overrides, the default light an environment map replaces), so
//! that a render through Python gives the command line's bytes; `tests/test_vkrt.py` compares them.

use crate::device::{self, Device};
use crate::errors::IntoPy;
use anyhow::{bail, Context as _, Result};
use clap::ValueEnum as _;
use glam::{Vec2, Vec3};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use vkrt::accel::LayoutKind;
use vkrt::bvh::{BuildConfig, BuilderKind};
use vkrt::cli::render::{view_and_upload, CameraArgs};
use vkrt::cli::sky::EnvmapArgs;
use vkrt::gpu_abi::{GpuHit, GpuRay};
use vkrt::prepare::cache::{prepare_scene, Cache, Storing};
use vkrt::prepare::{build_walk, GpuBvh, GpuScene, PrepareOptions, PreparedScene};
use vkrt::query::RayQuery;
use vkrt::scene::{Camera, Light, Material, SceneSummary, Triangle};

/// Where a scene came from: its file (read again only for what the prepared scene lacks: a
/// second layout for `trace`, `bvh_stats`), or arrays, kept.
pub enum Source {
    File(PathBuf),
    Arrays(Box<vkrt::scene::Scene>),
}

/// A layout's tree on the device and the query pipeline that walks it, made on first use.
struct Tracer {
    // Declared first, dropped first: the query's descriptors name the tree's buffers.
    query: RayQuery<'static>,
    /// None: the scene's own tree (`Scene::gpu`'s).
    _own_bvh: Option<GpuBvh<'static>>,
    layout: LayoutKind,
}

/// A scene on a device, ready to render and trace.
#[pyclass(module = "vkrt._vkrt", frozen)]
pub struct Scene {
    // Before `gpu`: dropped before the tree they may walk.
    tracers: Mutex<Vec<Tracer>>,
    /// `trace`'s rays gathered from numpy, kept between calls (its pages stay mapped).
    scratch: Mutex<Vec<GpuRay>>,
    pub device: &'static Device,
    pub source: Source,
    pub summary: SceneSummary,
    pub gpu: GpuScene<'static>,
    pub options: PrepareOptions,
    /// Whether `layout=` was given (else `trace` walks `vkrt trace`'s default).
    layout_given: bool,
    /// The sky as a checkpoint records it ("" for the scene's own).
    pub sky: String,
    /// The inputs' content hashes where the prepared-scene cache just checked them.
    pub input_hashes: Option<Vec<(PathBuf, u64)>>,
    pub warnings: Vec<String>,
}

// SAFETY: the raw pointers inside are host mappings of the scene's own device buffers (valid
// from any thread of the process). The scene is immutable once made (a frozen class: no method
// takes `&mut self`), its tracers sit behind a mutex, and every use of the device takes the
// device's turn (`Device::turn`), so shared references on several threads never touch a
// buffer or a queue at once.
unsafe impl Send for Scene {}
unsafe impl Sync for Scene {}

/// The camera and sky options `load_scene` and `Scene.from_arrays` take.
#[derive(Default)]
pub struct View {
    pub camera: CameraArgs,
    pub sky: Option<String>,
    pub envmap: EnvmapArgs,
    /// A resumed run's sky text (`cli::sky::sky_text`'s), used where `sky` and `envmap` are not.
    pub stored_sky: Option<String>,
}

fn vec3(name: &str, v: Option<Vec<f32>>) -> Result<Option<Vec3>> {
    match v {
        None => Ok(None),
        Some(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok(Some(Vec3::new(v[0], v[1], v[2]))),
        Some(v) => bail!("{name}={v:?}: expected three finite numbers x, y, z"),
    }
}

/// The camera and sky options as Python passes them (`_view` in python/vkrt/__init__.py: a dict
/// with every key, None where not given).
#[derive(FromPyObject, Default)]
#[pyo3(from_item_all)]
pub struct ViewArgs {
    camera: Option<u32>,
    eye: Option<Vec<f32>>,
    target: Option<Vec<f32>>,
    up: Option<Vec<f32>>,
    fov: Option<f32>,
    sky: Option<Vec<f32>>,
    envmap: Option<PathBuf>,
    envmap_scale: Option<f32>,
    envmap_rotate: Option<f32>,
}

impl View {
    pub fn new(args: ViewArgs) -> Result<Self> {
        let ViewArgs { camera, eye, target, up, fov, sky, envmap, envmap_scale, envmap_rotate } = args;
        if let Some(f) = fov {
            if !(f > 0.0 && f < 180.0) {
                bail!("fov={f}: the vertical field of view must be between 0 and 180 degrees");
            }
        }
        if envmap.is_some() && sky.is_some() {
            bail!("sky= and envmap= both given: an environment map is the sky");
        }
        if envmap.is_none() && (envmap_scale.is_some() || envmap_rotate.is_some()) {
            bail!("envmap_scale= and envmap_rotate= need envmap=");
        }
        if envmap_scale.is_some_and(|s| !(s >= 0.0 && s.is_finite())) {
            bail!("envmap_scale={}: must be a finite number >= 0", envmap_scale.unwrap_or(0.0));
        }
        let sky = match vec3("sky", sky)? {
            None => None,
            Some(s) if s.min_element() >= 0.0 => Some(format!("{},{},{}", s.x, s.y, s.z)),
            Some(s) => bail!("sky={s:?}: radiance cannot be negative"),
        };
        Ok(Self {
            camera: CameraArgs { camera, eye: vec3("eye", eye)?, target: vec3("target", target)?, up: vec3("up", up)?, fov, ..CameraArgs::default() },
            sky,
            envmap: EnvmapArgs { envmap, envmap_scale, envmap_rotate },
            stored_sky: None,
        })
    }
}

fn builder_named(name: Option<&str>) -> Result<BuilderKind> {
    match name {
        None => Ok(BuilderKind::default()),
        Some(n) => BuilderKind::from_str(n, true).map_err(|e| anyhow::anyhow!("builder={n:?}: {e}")),
    }
}

pub fn layout_named(name: &str) -> Result<LayoutKind> {
    LayoutKind::from_str(name, true).map_err(|e| anyhow::anyhow!("layout={name:?}: {e}"))
}

impl Scene {
    /// `load_scene`: the scene file prepared (through the user's prepared-scene cache, as `vkrt
    /// render`), viewed as `view` says and uploaded to `device`.
    pub fn load(path: &Path, view: &View, builder: Option<&str>, layout: Option<&str>, triangle_list: bool, device: Option<&str>) -> Result<Self> {
        let options = PrepareOptions {
            builder: builder_named(builder)?,
            layout: layout.map(layout_named).transpose()?.unwrap_or_default(),
            build: BuildConfig::default(),
            triangle_list,
        };
        let device = device::open(device)?;
        let cache = Cache::default_for_user();
        let mut warnings = Vec::new();
        let (prepared, _, storing, _) = prepare_scene(path, &options, cache.as_ref(), &mut |w| warnings.push(w))?;
        let mut summary = prepared.summary().clone();
        warnings.extend(summary.stats.warnings.iter().chain(prepared.downsampled()).cloned());
        let sky = vkrt::cli::sky::sky_text(&view.sky, &view.envmap, view.stored_sky.clone())?;
        let gpu = {
            let _turn = device.turn();
            let base = summary.camera;
            view_and_upload(&device.ctx, &prepared.arrays()?, &prepared.info(), &mut summary, &sky, &view.camera, base)?
        };
        let input_hashes = prepared.input_hashes().map(<[_]>::to_vec);
        drop(prepared);
        // The prepared-scene entry, written while the upload ran; a failure to store it only
        // costs the next load its time.
        if let Some(vkrt::prepare::cache::CacheOutcome::NotStored { why }) = storing.map(Storing::finish) {
            warnings.push(format!("prepared-scene cache: {why}"));
        }
        Ok(Self {
            tracers: Mutex::new(Vec::new()),
            scratch: Mutex::new(Vec::new()),
            device,
            source: Source::File(std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())),
            summary,
            gpu,
            options,
            layout_given: layout.is_some(),
            sky,
            input_hashes,
            warnings,
        })
    }

    /// `Scene.from_arrays`: a scene made in memory, prepared without the cache.
    pub fn from_scene(scene: vkrt::scene::Scene, view: &View, builder: Option<&str>, layout: Option<&str>, device: Option<&str>) -> Result<Self> {
        let options = PrepareOptions {
            builder: builder_named(builder)?,
            layout: layout.map(layout_named).transpose()?.unwrap_or_default(),
            build: BuildConfig::default(),
            triangle_list: true,
        };
        let device = device::open(device)?;
        let sky = vkrt::cli::sky::sky_text(&view.sky, &view.envmap, view.stored_sky.clone())?;
        let prepared = PreparedScene::new(&scene, &options)?;
        let mut summary = scene.summary();
        let gpu = {
            let _turn = device.turn();
            let base = summary.camera;
            view_and_upload(&device.ctx, &prepared.arrays(), &prepared.info, &mut summary, &sky, &view.camera, base)?
        };
        let warnings = summary.stats.warnings.clone();
        Ok(Self {
            tracers: Mutex::new(Vec::new()),
            scratch: Mutex::new(Vec::new()),
            device,
            source: Source::Arrays(Box::new(scene)),
            summary,
            gpu,
            options,
            layout_given: layout.is_some(),
            sky,
            input_hashes: None,
            warnings,
        })
    }

    /// The CPU scene: the arrays kept, or the file read again.
    fn cpu_scene(&self) -> Result<std::borrow::Cow<'_, vkrt::scene::Scene>> {
        match &self.source {
            Source::Arrays(s) => Ok(std::borrow::Cow::Borrowed(s)),
            Source::File(p) => Ok(std::borrow::Cow::Owned(vkrt::scene::load_scene(p)?)),
        }
    }

    /// The layout `trace` walks: the one asked for, else the scene's if `layout=` was given at
    /// load, else `vkrt trace`'s default (for a scene with instances, of its two-level BVH).
    fn trace_layout(&self, layout: Option<&str>) -> Result<LayoutKind> {
        // The uploaded BVH's triangles (every one once) and instances (0 for one level).
        let bvh = &self.gpu.bvh;
        let items = bvh.triangle_count as usize + bvh.instance_count as usize;
        Ok(match layout {
            Some(n) => layout_named(n)?,
            None if self.layout_given => self.options.layout,
            None => vkrt::cli::trace::default_layout(items, self.device.ctx.info.max_texel_buffer_elements, bvh.instance_count > 0),
        })
    }

    /// `trace`'s device work, with the GIL released, and its hits as words.
    fn traced<'py>(&self, py: Python<'py>, rays: &[GpuRay], any_hit: bool, layout: Option<&str>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let layout = self.trace_layout(layout).py_err()?;
        let hits = py
            .allow_threads(|| {
                let _turn = self.device.turn();
                self.trace_rays(rays, any_hit, layout)
            })
            .py_err()?;
        hit_words(py, hits)
    }

    /// Traces `rays` (in batches of `vkrt trace`'s size, so that its sorting decisions are
    /// the same) through `layout`'s tree; the device's turn must be held.
    fn trace_rays(&self, rays: &[GpuRay], any_hit: bool, layout: LayoutKind) -> Result<Vec<GpuHit>> {
        let mut tracers = self.tracers.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if !tracers.iter().any(|t| t.layout == layout) {
            let ctx = &self.device.ctx;
            let tracer = if layout == self.gpu.bvh.layout {
                Tracer { query: RayQuery::new(ctx, &self.gpu.bvh)?, _own_bvh: None, layout }
            } else {
                let scene = self.cpu_scene()?;
                let (flat, _) = build_walk(&scene, &PrepareOptions { layout, ..self.options })?;
                let bvh = GpuBvh::upload(ctx, &flat)?;
                Tracer { query: RayQuery::new(ctx, &bvh)?, _own_bvh: Some(bvh), layout }
            };
            tracer.query.warm_up()?;
            tracers.push(tracer);
        }
        let Some(tracer) = tracers.iter().find(|t| t.layout == layout) else { bail!("no tracer for layout {}", layout.name()) };
        let mut hits = Vec::with_capacity(rays.len());
        for batch in rays.chunks(vkrt::cli::trace::FILE_BATCH) {
            hits.extend(tracer.query.trace(batch, any_hit).context("tracing a batch of rays")?);
        }
        Ok(hits)
    }
}

/// Rays per parallel task of the gather and the checks: large enough that a task's start costs
/// nothing next to it.
const CHUNK: usize = 1 << 14;

/// Whether the device can trace `r` (what `vkrt.Scene.trace` promises to refuse otherwise).
/// Without short-circuits (`&`, `|`), so that the check of a million rays vectorises: with
/// `&&` and an iterator it took 10-16 ms of a 150 ms trace.
fn usable(r: &GpuRay) -> bool {
    let ([ox, oy, oz], [dx, dy, dz]) = (r.origin, r.direction);
    let finite = ox.is_finite() & oy.is_finite() & oz.is_finite() & dx.is_finite() & dy.is_finite() & dz.is_finite();
    finite & ((dx != 0.0) | (dy != 0.0) | (dz != 0.0)) & (r.tmin >= 0.0) & !r.tmax.is_nan()
}

/// The error for the first unusable ray, `i`.
fn unusable(i: usize, r: &GpuRay) -> anyhow::Error {
    if !r.origin.iter().chain(&r.direction).all(|x| x.is_finite()) {
        anyhow::anyhow!("ray {i}: origin {:?} and direction {:?} must be finite", r.origin, r.direction)
    } else if r.direction == [0.0; 3] {
        anyhow::anyhow!("ray {i}: the direction is zero")
    } else {
        anyhow::anyhow!("ray {i}: tmin {} and tmax {} must be numbers, tmin >= 0", r.tmin, r.tmax)
    }
}

/// Fails naming the first ray the device cannot trace; checked on every core.
fn check_rays(rays: &[GpuRay]) -> Result<()> {
    use rayon::prelude::*;
    let first_bad = rays.par_chunks(CHUNK).enumerate().filter_map(|(c, chunk)| chunk.iter().position(|r| !usable(r)).map(|k| c * CHUNK + k)).min();
    match first_bad {
        Some(i) => Err(unusable(i, &rays[i])),
        None => Ok(()),
    }
}

/// Rays from numpy: origins and directions (N, 3), tmin and tmax (N,) (broadcast by the
/// Python layer), read in place whatever their strides and gathered into the device's layout on
/// every core, checked on the way.
fn gather_rays(
    origins: &PyReadonlyArray2<f32>,
    directions: &PyReadonlyArray2<f32>,
    tmin: &PyReadonlyArray1<f32>,
    tmax: &PyReadonlyArray1<f32>,
    rays: &mut Vec<GpuRay>,
) -> Result<()> {
    use rayon::prelude::*;
    let (o, d, t0, t1) = (origins.as_array(), directions.as_array(), tmin.as_array(), tmax.as_array());
    let n = o.nrows();
    if o.ncols() != 3 || d.ncols() != 3 || d.nrows() != n || t0.len() != n || t1.len() != n {
        bail!("origins {:?} and directions {:?} must both have shape (N, 3), tmin and tmax (N,)", origins.shape(), directions.shape());
    }
    // Into the scene's scratch vector: a fresh one per call cost its page faults, a third of the
    // gather's time on a million rays.
    rays.resize(n, GpuRay { origin: [0.0; 3], tmin: 0.0, direction: [0.0; 3], tmax: 0.0 });
    let first_bad = rays
        .par_chunks_mut(CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut first = None;
            for (k, ray) in chunk.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                // SAFETY: i < n, the rows of every view (checked above), and columns 0..3 exist
                // in both (N, 3) views. Unchecked: the gather is most of what `trace` adds to
                // the device's time, and bounds checks were a good part of it.
                *ray = unsafe {
                    GpuRay {
                        origin: [*o.uget([i, 0]), *o.uget([i, 1]), *o.uget([i, 2])],
                        tmin: *t0.uget(i),
                        direction: [*d.uget([i, 0]), *d.uget([i, 1]), *d.uget([i, 2])],
                        tmax: *t1.uget(i),
                    }
                };
                if first.is_none() && !usable(ray) {
                    first = Some(i);
                }
            }
            first
        })
        .reduce(|| None, |a, b| a.into_iter().chain(b).min());
    if let Some(i) = first_bad {
        return Err(unusable(i, &rays[i]));
    }
    Ok(())
}

// The hits go to Python as the device wrote them: eight 4-byte words per ray, whose fields the
// Python layer views by name (python/vkrt/__init__.py, `_HIT_DTYPE`).
const _: () = assert!(std::mem::size_of::<GpuHit>() == 32 && std::mem::align_of::<GpuHit>() == 4);

/// The hits as an (N, 8) uint32 array that owns their memory: no copy.
fn hit_words<'py>(py: Python<'py>, hits: Vec<GpuHit>) -> PyResult<Bound<'py, PyArray2<u32>>> {
    let n = hits.len();
    let words: Vec<u32> = bytemuck::allocation::cast_vec(hits);
    PyArray1::from_vec(py, words).reshape([n, 8])
}

fn columns<'py>(py: Python<'py>, rows: &[vkrt::cli::bvh::Row]) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    macro_rules! column {
        ($name:expr, $f:expr) => {
            dict.set_item($name, PyList::new(py, rows.iter().map($f))?)?
        };
    }
    column!("scene", |r| r.scene.clone());
    column!("triangles", |r| r.triangles);
    column!("builder", |r| r.builder.name().to_string());
    column!("layout", |r| r.layout_name());
    column!("build_ms", |r| r.build_ms);
    column!("nodes", |r| r.nodes);
    column!("bytes", |r| r.bytes);
    column!("sah", |r| r.sah);
    for (kind, pick) in [("primary", 0usize), ("shadow", 1), ("diffuse", 2)] {
        let stats = |r: &vkrt::cli::bvh::Row| [r.primary, r.shadow, r.diffuse][pick];
        column!(format!("{kind}_nodes_per_ray"), |r| stats(r).nodes_per_ray);
        column!(format!("{kind}_tris_per_ray"), |r| stats(r).tris_per_ray);
        column!(format!("{kind}_rays_per_second"), |r| stats(r).rays_per_second);
    }
    Ok(dict)
}

#[pymethods]
impl Scene {
    /// Traces rays; see `vkrt.Scene.trace` (python/vkrt/__init__.py) for the contract.
    #[pyo3(signature = (origins, directions, tmin, tmax, any_hit=false, layout=None))]
    #[allow(clippy::too_many_arguments)]
    fn _trace<'py>(
        &self,
        py: Python<'py>,
        origins: PyReadonlyArray2<'py, f32>,
        directions: PyReadonlyArray2<'py, f32>,
        tmin: PyReadonlyArray1<'py, f32>,
        tmax: PyReadonlyArray1<'py, f32>,
        any_hit: bool,
        layout: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let mut rays = self.scratch.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        gather_rays(&origins, &directions, &tmin, &tmax, &mut rays).py_err()?;
        self.traced(py, &rays, any_hit, layout)
    }

    /// Traces an (N, 8) float32 array in `vkrt trace`'s layout (origin, tmin, direction, tmax),
    /// read in place when it is C-contiguous.
    #[pyo3(signature = (rays, any_hit=false, layout=None))]
    fn _trace_packed<'py>(
        &self,
        py: Python<'py>,
        rays: PyReadonlyArray2<'py, f32>,
        any_hit: bool,
        layout: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<u32>>> {
        if rays.shape()[1] != 8 {
            return Err(pyo3::exceptions::PyValueError::new_err(format!("rays must have shape (N, 8), not {:?}", rays.shape())));
        }
        let copied: Vec<GpuRay>;
        let rays: &[GpuRay] = match rays.as_slice() {
            Ok(floats) => bytemuck::cast_slice(floats),
            Err(_) => {
                let a = rays.as_array();
                copied = a.rows().into_iter().map(|r| GpuRay { origin: [r[0], r[1], r[2]], tmin: r[3], direction: [r[4], r[5], r[6]], tmax: r[7] }).collect();
                &copied
            }
        };
        check_rays(rays).py_err()?;
        self.traced(py, rays, any_hit, layout)
    }

    /// What `vkrt bvh` prints for this scene, as columns (a dict of lists).
    #[pyo3(signature = (builders=None, layouts=None, width=384, height=384, repeat=3))]
    fn _bvh_stats<'py>(
        &self,
        py: Python<'py>,
        builders: Option<Vec<String>>,
        layouts: Option<Vec<String>>,
        width: u32,
        height: u32,
        repeat: u32,
    ) -> PyResult<Bound<'py, PyDict>> {
        if width == 0 || height == 0 || repeat == 0 {
            return Err(pyo3::exceptions::PyValueError::new_err(format!("width={width}, height={height}, repeat={repeat}: each must be at least 1")));
        }
        let builders = builders.unwrap_or_default().iter().map(|b| builder_named(Some(b))).collect::<Result<Vec<_>>>().py_err()?;
        let layouts = layouts.unwrap_or_default().iter().map(|l| layout_named(l)).collect::<Result<Vec<_>>>().py_err()?;
        let name = match &self.source {
            Source::File(p) => p.clone(),
            Source::Arrays(_) => PathBuf::from("arrays"),
        };
        let args = vkrt::cli::bvh::BvhArgs {
            scenes: vec![name.clone()],
            format: vkrt::cli::bvh::Format::Table,
            width,
            height,
            repeat,
            heatmap: None,
            heatmap_builder: BuilderKind::default(),
            heatmap_layout: LayoutKind::Threaded,
            builders,
            layouts,
            device: vkrt::cli::DeviceArgs { device: None },
        };
        let rows = py
            .allow_threads(|| -> Result<_> {
                let mut scene = self.cpu_scene()?.into_owned();
                // `vkrt bvh` measures from the camera the rays start at: this scene's.
                scene.camera = self.summary.camera;
                let _turn = self.device.turn();
                vkrt::cli::bvh::scene_rows(&self.device.ctx, &name, &scene, &args)
            })
            .py_err()?;
        columns(py, &rows)
    }

    /// Triangles after degenerate ones were dropped (hit `prim` indexes them).
    #[getter]
    fn triangle_count(&self) -> usize {
        self.summary.triangles
    }

    /// The builder and layout the scene was prepared with.
    #[getter]
    fn builder(&self) -> String {
        self.options.builder.name().to_string()
    }

    #[getter]
    fn layout(&self) -> String {
        self.options.layout.name().to_string()
    }

    /// The camera renders use: eye, target, up, vertical field of view in degrees.
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = &self.summary.camera;
        let dict = PyDict::new(py);
        dict.set_item("eye", c.eye.to_array())?;
        dict.set_item("target", c.target.to_array())?;
        dict.set_item("up", c.up.to_array())?;
        dict.set_item("fov", c.fov_y_deg)?;
        Ok(dict)
    }

    /// The device the scene lives on.
    #[getter]
    fn device(&self) -> String {
        self.device.ctx.info.name.clone()
    }

    /// What loading warned about (also given to Python's `warnings`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The scene file, or None for a scene made from arrays.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        match &self.source {
            Source::File(p) => Some(p.clone()),
            Source::Arrays(_) => None,
        }
    }

    fn __repr__(&self) -> String {
        let from = match &self.source {
            Source::File(p) => p.display().to_string(),
            Source::Arrays(_) => "arrays".to_string(),
        };
        format!(
            "<vkrt.Scene {from}: {} triangles, {} / {} on {}>",
            self.summary.triangles,
            self.options.builder.name(),
            self.options.layout.name(),
            self.device.ctx.info.name
        )
    }
}

/// `vkrt.load_scene`: see python/vkrt/__init__.py.
#[pyfunction]
#[pyo3(signature = (path, view, builder=None, layout=None, triangle_list=true, device=None))]
pub fn _load_scene(
    py: Python<'_>,
    path: PathBuf,
    view: ViewArgs,
    builder: Option<String>,
    layout: Option<String>,
    triangle_list: bool,
    device: Option<String>,
) -> PyResult<Scene> {
    let view = View::new(view).py_err()?;
    py.allow_threads(|| Scene::load(&path, &view, builder.as_deref(), layout.as_deref(), triangle_list, device.as_deref())).py_err()
}

fn get<'py, T: FromPyObject<'py>>(d: &Bound<'py, PyDict>, key: &str, what: &str) -> Result<Option<T>> {
    match d.get_item(key) {
        Ok(Some(v)) if !v.is_none() => v.extract::<T>().map(Some).map_err(|e| anyhow::anyhow!("{what}[{key:?}]: {e}")),
        _ => Ok(None),
    }
}

fn colour(v: Option<Vec<f32>>, what: &str, default: Vec3) -> Result<Vec3> {
    match v {
        None => Ok(default),
        Some(c) if c.len() == 3 && c.iter().all(|x| x.is_finite() && *x >= 0.0) => Ok(Vec3::new(c[0], c[1], c[2])),
        Some(c) => bail!("{what}: {c:?} is not three finite numbers >= 0"),
    }
}

const MATERIAL_KEYS: [&str; 9] = ["name", "diffuse", "specular", "shininess", "emission", "ior", "illum", "metallic", "roughness"];

/// A material from a dict: MTL's Kd/Ks/Ns/Ke/Ni/illum as `diffuse`, `specular`, `shininess`,
/// `emission`, `ior`, `illum`, or glTF's metallic-roughness with `metallic` and `roughness`.
fn material(i: usize, d: &Bound<'_, PyDict>) -> Result<Material> {
    let what = format!("materials[{i}]");
    for key in d.keys() {
        let key: String = key.extract().map_err(|_| anyhow::anyhow!("{what}: keys must be strings"))?;
        if !MATERIAL_KEYS.contains(&key.as_str()) {
            bail!("{what}: unknown key {key:?} (known: {})", MATERIAL_KEYS.join(", "));
        }
    }
    let base = Material::default();
    let mut m = Material {
        name: get(d, "name", &what)?.unwrap_or_else(|| format!("material{i}")),
        diffuse: colour(get(d, "diffuse", &what)?, &format!("{what}[\"diffuse\"]"), base.diffuse)?,
        specular: colour(get(d, "specular", &what)?, &format!("{what}[\"specular\"]"), base.specular)?,
        emission: colour(get(d, "emission", &what)?, &format!("{what}[\"emission\"]"), base.emission)?,
        shininess: get(d, "shininess", &what)?.unwrap_or(base.shininess),
        ior: get(d, "ior", &what)?.unwrap_or(base.ior),
        illum: get(d, "illum", &what)?.unwrap_or(base.illum),
        ..base
    };
    if !(m.shininess >= 0.0 && m.shininess.is_finite() && m.ior >= 1.0 && m.ior.is_finite()) || m.illum > 10 {
        bail!("{what}: shininess {} must be >= 0, ior {} >= 1, illum {} 0 to 10", m.shininess, m.ior, m.illum);
    }
    let metallic: Option<f32> = get(d, "metallic", &what)?;
    let roughness: Option<f32> = get(d, "roughness", &what)?;
    if metallic.is_some() || roughness.is_some() {
        let (metallic, roughness) = (metallic.unwrap_or(0.0), roughness.unwrap_or(1.0));
        if !((0.0..=1.0).contains(&metallic) && (0.0..=1.0).contains(&roughness)) {
            bail!("{what}: metallic {metallic} and roughness {roughness} must be in [0, 1]");
        }
        m.metallic_roughness = Some(vkrt::scene::material::MetallicRoughness { metallic, roughness, texture: None });
    }
    Ok(m)
}

/// A light from a dict: `{"type": "point", "position", "intensity"}` or `{"type":
/// "directional", "direction", "intensity"}`.
fn light(i: usize, d: &Bound<'_, PyDict>) -> Result<Light> {
    let what = format!("lights[{i}]");
    let kind: String = get(d, "type", &what)?.with_context(|| format!("{what}: needs \"type\": \"point\" or \"directional\""))?;
    let intensity = colour(get(d, "intensity", &what)?, &format!("{what}[\"intensity\"]"), Vec3::ONE)?;
    let v = |key: &str| -> Result<Vec3> {
        let v = vec3(&format!("{what}[{key:?}]"), get(d, key, &what)?)?;
        v.with_context(|| format!("{what}: a {kind} light needs {key:?}"))
    };
    match kind.as_str() {
        "point" => Ok(Light::Point { position: v("position")?, intensity }),
        "directional" => {
            let direction = v("direction")?;
            if direction == Vec3::ZERO {
                bail!("{what}: the direction is zero");
            }
            Ok(Light::Directional { direction: direction.normalize(), intensity })
        }
        other => bail!("{what}: type {other:?} is not \"point\" or \"directional\""),
    }
}

/// `vkrt.Scene.from_arrays`: see python/vkrt/__init__.py.
#[pyfunction]
#[pyo3(signature = (vertices, triangles, material_ids, materials, lights, normals, uvs, view, builder=None, layout=None, device=None))]
#[allow(clippy::too_many_arguments)]
pub fn _scene_from_arrays(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    triangles: PyReadonlyArray2<'_, u32>,
    material_ids: Option<PyReadonlyArray1<'_, u32>>,
    materials: Option<Vec<Bound<'_, PyDict>>>,
    lights: Option<Vec<Bound<'_, PyDict>>>,
    normals: Option<PyReadonlyArray2<'_, f32>>,
    uvs: Option<PyReadonlyArray2<'_, f32>>,
    view: ViewArgs,
    builder: Option<String>,
    layout: Option<String>,
    device: Option<String>,
) -> PyResult<Scene> {
    let view = View::new(view).py_err()?;
    let mut materials: Vec<Material> = materials.unwrap_or_default().iter().enumerate().map(|(i, d)| material(i, d)).collect::<Result<_>>().py_err()?;
    if materials.is_empty() {
        materials.push(Material::default());
    }
    let lights = lights.unwrap_or_default().iter().enumerate().map(|(i, d)| light(i, d)).collect::<Result<_>>().py_err()?;
    let mut scene = vkrt::scene::Scene { materials, lights, ..vkrt::scene::Scene::default() };
    let (v, t) = (vertices.as_array(), triangles.as_array());
    let n = v.nrows();
    let bad = |m: String| Err(pyo3::exceptions::PyValueError::new_err(m));
    if v.ncols() != 3 || t.ncols() != 3 {
        return bad(format!("vertices {:?} must be (N, 3) and triangles {:?} (M, 3)", vertices.shape(), triangles.shape()));
    }
    if let Some(i) = (0..n).find(|&i| !(0..3).all(|k| v[[i, k]].is_finite())) {
        return bad(format!("vertices[{i}] is not finite: {:?}", [v[[i, 0]], v[[i, 1]], v[[i, 2]]]));
    }
    let normals = normals.as_ref().map(|a| a.as_array());
    let uvs = uvs.as_ref().map(|a| a.as_array());
    if normals.as_ref().is_some_and(|a| a.nrows() != n || a.ncols() != 3) || uvs.as_ref().is_some_and(|a| a.nrows() != n || a.ncols() != 2) {
        return bad(format!("normals must be ({n}, 3) and uvs ({n}, 2), one per vertex"));
    }
    let ids = material_ids.as_ref().map(|a| a.as_array());
    if ids.as_ref().is_some_and(|a| a.len() != t.nrows()) {
        return bad(format!("material_ids must have one entry per triangle ({})", t.nrows()));
    }
    let vertex = |i: usize| Vec3::new(v[[i, 0]], v[[i, 1]], v[[i, 2]]);
    for j in 0..t.nrows() {
        let idx = [t[[j, 0]] as usize, t[[j, 1]] as usize, t[[j, 2]] as usize];
        if let Some(&bad_index) = idx.iter().find(|&&i| i >= n) {
            return bad(format!("triangles[{j}] names vertex {bad_index}; there are {n}"));
        }
        let material = ids.as_ref().map_or(0, |a| a[j]);
        if material as usize >= scene.materials.len() {
            return bad(format!("material_ids[{j}] is {material}; there are {} materials", scene.materials.len()));
        }
        let tri = Triangle {
            p: idx.map(vertex),
            n: normals.as_ref().map(|a| idx.map(|i| Vec3::new(a[[i, 0]], a[[i, 1]], a[[i, 2]]))),
            uv: uvs.as_ref().map(|a| idx.map(|i| Vec2::new(a[[i, 0]], a[[i, 1]]))),
            material,
        };
        vkrt::scene::assemble::push_triangle(&mut scene, tri);
    }
    let cameras: Vec<Camera> = Vec::new();
    // Errors name the scene "arrays"; each is the arrays' fault, never a missing file.
    vkrt::scene::assemble::finish_scene(&mut scene, Path::new("arrays"), cameras).map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("{e:#}")))?;
    vkrt::scene::assemble::light_if_unlit(&mut scene, vkrt::scene::assemble::DEFAULT_AMBIENT);
    py.allow_threads(|| Scene::from_scene(scene, &view, builder.as_deref(), layout.as_deref(), device.as_deref())).py_err()
}
