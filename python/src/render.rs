//! Rendering from Python: `vkrt.render` (one call, the command line's image) and
//! `vkrt.Progressive` (the command line's progressive run, step by step: add samples, read the
//! image and the error estimate, save and resume checkpoints, merge runs).
//!
//! The settings are resolved by the command line's own rules (`cli::render_path::path_settings`
//! with no expert flags, `stop_rules`), so a render here and `vkrt render` with the same size,
//! seed and samples write the same bytes. The GIL is released while the device works; between
//! batches the run takes it back briefly to report progress and to look for Ctrl-C
//! (`KeyboardInterrupt`: the samples finished so far stay in the run).

use crate::errors::IntoPy;
use crate::scene::Scene;
use anyhow::{bail, Result};
use numpy::{PyArray1, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use vkrt::cli::progress::{Progress, Status};
use vkrt::cli::render::{camera_numbers, check_image_size, IntegratorKind, DEFAULT_SIZE, WHITTED_DEFAULT_DEPTH};
use vkrt::cli::render_path::{self, PathArgs, PathRun, DEFAULT_CHECKPOINT_INTERVAL_S, DEFAULT_SAMPLES_PER_BATCH};
use vkrt::integrator::path::checkpoint::{hash_inputs, Checkpoint, Identity, InputHash, RunSettings};
use vkrt::integrator::path::{self, Accumulation, Hooks, PathProgress, PathSettings, Stop};
use vkrt::integrator::{whitted, Image, RenderSettings};

/// An image as numpy wants it: (height, width, 3) float32, top row first.
pub fn to_numpy<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let flat: Vec<f32> = image.pixels.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat).reshape([image.height as usize, image.width as usize, 3])
}

/// How a run shows its progress: vkrt's bar on stderr, a Python callable, or nothing.
pub enum Report {
    Quiet,
    Bar,
    Callback(Py<PyAny>),
}

impl Report {
    pub fn from_arg(progress: Option<Bound<'_, PyAny>>) -> PyResult<Self> {
        match progress {
            None => Ok(Report::Bar),
            Some(p) if p.is_callable() => Ok(Report::Callback(p.unbind())),
            Some(p) => Ok(if p.is_truthy()? { Report::Bar } else { Report::Quiet }),
        }
    }
}

/// What a run does between batches, with the GIL taken back: report progress, and stop at
/// Ctrl-C (or at an exception from the callback), keeping the error to raise once the device
/// is done.
struct Between<'r> {
    report: &'r Report,
    bar: Progress,
    /// Raised to stop the run after its current batch (the path tracer's `Hooks::interrupt`).
    stop: &'r AtomicBool,
    error: Option<PyErr>,
}

impl<'r> Between<'r> {
    fn new(report: &'r Report, what: &'static str, stop: &'r AtomicBool) -> Self {
        Self { report, bar: Progress::new(what, !matches!(report, Report::Bar)), stop, error: None }
    }

    fn step(&mut self, status: Status, details: impl FnOnce(Python<'_>) -> PyResult<Bound<'_, PyDict>>) {
        self.bar.update(&status);
        let result = Python::with_gil(|py| -> PyResult<()> {
            py.check_signals()?;
            if let Report::Callback(f) = self.report {
                f.call1(py, (details(py)?,))?;
            }
            Ok(())
        });
        if let Err(e) = result {
            self.error.get_or_insert(e);
            self.stop.store(true, Ordering::SeqCst);
        }
    }

    fn finish(self) -> PyResult<()> {
        self.bar.finish();
        // A Ctrl-C that came during the last batch, after the last look.
        Python::with_gil(|py| py.check_signals())?;
        self.error.map_or(Ok(()), Err)
    }
}

/// The image settings both integrators share, checked against the device.
fn image_settings(scene: &Scene, width: u32, height: u32, seed: u32, integrator: IntegratorKind) -> Result<RenderSettings> {
    if width == 0 || height == 0 {
        bail!("width={width}, height={height}: an image has at least one pixel each way");
    }
    check_image_size(&scene.device.ctx.info, width, height, integrator)?;
    Ok(RenderSettings { width, height, seed, samples_per_batch: DEFAULT_SAMPLES_PER_BATCH, ..RenderSettings::default() })
}

/// `vkrt.render(integrator="whitted")`.
fn whitted_image(py: Python<'_>, scene: &Scene, settings: &RenderSettings, report: &Report) -> PyResult<Image> {
    let stop = AtomicBool::new(false);
    let mut between = Between::new(report, "rendering", &stop);
    let image = py.allow_threads(|| {
        let _turn = scene.device.turn();
        whitted::render(&scene.device.ctx, &scene.gpu, settings, &mut |done, total| {
            let fraction = done as f64 / total.max(1) as f64;
            between.step(Status { fraction, count: Some((done, Some(total), "tiles")), ..Status::default() }, |py| {
                let d = PyDict::new(py);
                d.set_item("fraction", fraction)?;
                d.set_item("tiles", done)?;
                d.set_item("total_tiles", total)?;
                Ok(d)
            })
        })
    });
    between.finish()?;
    image.py_err().map(|(image, _)| image)
}

/// Progressive(scene, spp=None, width=512, height=512, seed=0, max_depth=None)
///
/// A progressive path-traced run: the command line's `vkrt render --integrator path`, step by
/// step. `spp` is the run's planned total (it sizes the Z-ordered sample sets; adding past it
/// is allowed); without it the run is planned as one stopped by time or error.
///
///     run = vkrt.Progressive(scene, spp=256, width=320, height=240)
///     run.add(16)                  # 16 more samples per pixel
///     run.add(seconds=10)          # or for 10 s, or until run.relmse <= target_relmse
///     image = run.image()          # (height, width, 3) float32, linear radiance
///     run.save("run.ckpt")         # vkrt render --resume run.ckpt, or vkrt.resume(...)
///
/// Steps add up to the bytes of one run of the same total (and of the command line's).
#[pyclass(module = "vkrt._vkrt")]
pub struct Progressive {
    scene: Py<Scene>,
    settings: PathSettings,
    seed: u32,
    acc: Option<Accumulation>,
    /// Samples planned when the run was made (they size the Z-ordered sample sets).
    planned: Option<u64>,
    seconds: f64,
    rays: u64,
}

impl Progressive {
    fn create(scene: Py<Scene>, s: &Scene, width: u32, height: u32, seed: u32, spp: Option<u64>, max_depth: Option<u32>) -> Result<Self> {
        if max_depth == Some(0) {
            bail!("max_depth=0: a path has at least one ray");
        }
        let image = image_settings(s, width, height, seed, IntegratorKind::Path)?;
        // The command line's rules with no expert flag: a run of `spp` samples, or one stopped
        // by other rules (the sample sets of a 256-spp run).
        let settings = render_path::path_settings(&PathArgs::default(), image, max_depth, None, Stop { spp, ..Stop::default() });
        Ok(Self { scene, settings, seed, acc: None, planned: spp, seconds: 0.0, rays: 0 })
    }

    /// The run as a checkpoint records it (the scene's inputs hashed, as `vkrt render
    /// --checkpoint` does).
    fn run_settings(&self, s: &Scene) -> Result<RunSettings> {
        let crate::scene::Source::File(scene_path) = &s.source else {
            bail!("a checkpoint records the scene file it renders: this scene was made from arrays");
        };
        let inputs = match &s.input_hashes {
            Some(known) => known.iter().map(|(p, hash)| InputHash { path: p.display().to_string(), hash: *hash }).collect(),
            None => hash_inputs(&s.summary.stats.inputs)?,
        };
        let camera = camera_numbers(&s.summary.camera);
        let run = self.path_run(s, scene_path.display().to_string());
        let identity = Identity::Inputs { inputs, sky: s.sky.clone(), camera };
        Ok(render_path::run_settings(&run, identity, path::connections::connects(&self.settings, &s.gpu)))
    }

    fn path_run<'a>(&self, s: &'a Scene, scene_path: String) -> PathRun<'a> {
        PathRun {
            scene: &s.summary,
            input_hashes: None,
            scene_path,
            sky: s.sky.clone(),
            camera: camera_numbers(&s.summary.camera),
            settings: PathSettings { stop: Stop { spp: self.planned, ..Stop::default() }, ..self.settings },
            seed: self.seed,
            output: String::new(),
            builder: s.options.builder.name().to_string(),
            layout: s.options.layout.name().to_string(),
            checkpoint: None,
            checkpoint_interval: DEFAULT_CHECKPOINT_INTERVAL_S,
            resume: None,
            resume_path: None,
            shard: None,
            preview_every: None,
        }
    }

    /// Runs until `stop` holds (samples counted from the start of the run).
    fn run(&mut self, py: Python<'_>, stop: Stop, report: &Report) -> PyResult<()> {
        let scene = self.scene.get();
        let settings = PathSettings { stop, ..self.settings };
        let resume = self.acc.take();
        let stop_flag = AtomicBool::new(false);
        let mut between = Between::new(report, "rendering", &stop_flag);
        let result = py.allow_threads(|| {
            let mut on_progress = |p: &PathProgress| {
                let status = Status {
                    fraction: p.fraction,
                    start_fraction: p.start_fraction,
                    count: Some((p.samples, p.target_spp, "spp")),
                    rays_per_second: p.rays_per_second,
                    relmse: p.relmse,
                };
                between.step(status, |py| {
                    let d = PyDict::new(py);
                    d.set_item("spp", p.samples)?;
                    d.set_item("target_spp", p.target_spp)?;
                    d.set_item("fraction", p.fraction)?;
                    d.set_item("seconds", p.seconds)?;
                    d.set_item("relmse", p.relmse)?;
                    d.set_item("rays_per_second", p.rays_per_second)?;
                    Ok(d)
                });
            };
            let mut hooks = Hooks {
                progress: Some(&mut on_progress),
                checkpoint: None,
                checkpoint_interval_s: f64::INFINITY,
                snapshot: None,
                snapshot_interval_s: f64::INFINITY,
                interrupt: Some(&stop_flag),
            };
            let _turn = scene.device.turn();
            path::render(&scene.device.ctx, &scene.gpu, &settings, resume.clone(), &mut hooks)
        });
        let outcome = between.finish();
        match result {
            Ok((acc, stats)) => {
                self.seconds += stats.seconds;
                self.rays += stats.rays;
                self.acc = Some(acc);
            }
            Err(e) => {
                self.acc = resume;
                return Err(crate::errors::to_py(e));
            }
        }
        outcome
    }
}

#[pymethods]
impl Progressive {
    #[new]
    #[pyo3(signature = (scene, spp=None, width=None, height=None, seed=0, max_depth=None))]
    fn py_new(
        py: Python<'_>,
        scene: Py<Scene>,
        spp: Option<u64>,
        width: Option<u32>,
        height: Option<u32>,
        seed: u32,
        max_depth: Option<u32>,
    ) -> PyResult<Self> {
        if spp == Some(0) {
            return Err(pyo3::exceptions::PyValueError::new_err("spp=0: a run plans at least one sample per pixel"));
        }
        let s = scene.bind(py).get();
        Self::create(scene.clone_ref(py), s, width.unwrap_or(DEFAULT_SIZE), height.unwrap_or(DEFAULT_SIZE), seed, spp, max_depth).py_err()
    }

    /// Adds samples: `spp` more per pixel, or until `seconds` pass or the estimated relMSE
    /// reaches `target_relmse` (the first rule to hold).
    #[pyo3(signature = (spp=None, seconds=None, target_relmse=None, progress=None))]
    fn add(&mut self, py: Python<'_>, spp: Option<u64>, seconds: Option<f64>, target_relmse: Option<f64>, progress: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let report = Report::from_arg(progress)?;
        if spp == Some(0) || seconds.is_some_and(|s| !(s > 0.0)) || target_relmse.is_some_and(|e| !(e > 0.0)) {
            return Err(pyo3::exceptions::PyValueError::new_err("spp, seconds and target_relmse must be positive"));
        }
        if spp.is_none() && seconds.is_none() && target_relmse.is_none() {
            return Err(pyo3::exceptions::PyValueError::new_err("add() needs spp, seconds or target_relmse"));
        }
        let done = self.acc.as_ref().map_or(0, |a| a.samples);
        self.run(py, Stop { spp: spp.map(|n| done + n), seconds, target_relmse }, &report)
    }

    /// The image so far: linear radiance, (height, width, 3) float32.
    fn image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let image = match &self.acc {
            Some(a) => a.image(),
            None => Image::new(self.settings.image.width, self.settings.image.height),
        };
        to_numpy(py, &image)
    }

    /// Samples per pixel taken so far.
    #[getter]
    fn spp(&self) -> u64 {
        self.acc.as_ref().map_or(0, |a| a.samples)
    }

    /// The relMSE estimated from two half-images (as `--target-relmse` reads it), or None
    /// before there are samples to compare.
    #[getter]
    fn relmse(&self) -> Option<f64> {
        self.acc.as_ref().and_then(Accumulation::estimate_relmse)
    }

    /// Device seconds and rays traced so far.
    #[getter]
    fn seconds(&self) -> f64 {
        self.seconds
    }

    #[getter]
    fn rays(&self) -> u64 {
        self.rays
    }

    #[getter]
    fn width(&self) -> u32 {
        self.settings.image.width
    }

    #[getter]
    fn height(&self) -> u32 {
        self.settings.image.height
    }

    #[getter]
    fn seed(&self) -> u32 {
        self.seed
    }

    /// Writes a checkpoint `vkrt render --resume` (and `vkrt.resume`) continue, atomically.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let scene = self.scene.get();
        let acc = self.acc.clone().unwrap_or_else(|| Accumulation::new(self.settings.image.width, self.settings.image.height));
        py.allow_threads(|| -> Result<()> {
            let settings = self.run_settings(scene)?;
            Checkpoint { settings, accum: acc }.write(&path)
        })
        .py_err()
    }

    fn __repr__(&self) -> String {
        format!("<vkrt.Progressive {}x{}, {} spp, seed {}>", self.settings.image.width, self.settings.image.height, self.spp(), self.seed)
    }
}

/// `vkrt.render`: see python/vkrt/__init__.py.
#[pyfunction]
#[pyo3(signature = (scene, spp=None, integrator="path", width=None, height=None, seed=0, max_depth=None, seconds=None, target_relmse=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn _render<'py>(
    py: Python<'py>,
    scene: Py<Scene>,
    spp: Option<u64>,
    integrator: &str,
    width: Option<u32>,
    height: Option<u32>,
    seed: u32,
    max_depth: Option<u32>,
    seconds: Option<f64>,
    target_relmse: Option<f64>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let report = Report::from_arg(progress)?;
    let (width, height) = (width.unwrap_or(DEFAULT_SIZE), height.unwrap_or(DEFAULT_SIZE));
    let s = scene.bind(py).get();
    let bad = |m: String| Err(pyo3::exceptions::PyValueError::new_err(m));
    if spp == Some(0) {
        return bad("spp=0: at least one sample per pixel".into());
    }
    match integrator {
        "whitted" => {
            if seconds.is_some() || target_relmse.is_some() {
                return bad("seconds= and target_relmse= need integrator=\"path\" (the Whitted integrator renders its samples once)".into());
            }
            let Ok(spp) = u32::try_from(spp.unwrap_or(1)) else { return bad(format!("spp={}: too many for the Whitted integrator", spp.unwrap_or(0))) };
            let depth = max_depth.unwrap_or(WHITTED_DEFAULT_DEPTH);
            if !(1..=whitted::MAX_DEPTH).contains(&depth) {
                return bad(format!("max_depth={depth}: the Whitted integrator traces 1 to {} rays per path", whitted::MAX_DEPTH));
            }
            let settings = RenderSettings { spp, max_depth: depth, ..image_settings(s, width, height, seed, IntegratorKind::Whitted).py_err()? };
            let image = whitted_image(py, s, &settings, &report)?;
            to_numpy(py, &image)
        }
        "path" => {
            let stop = render_path::stop_rules(
                spp.map(|n| n.min(u64::from(u32::MAX)) as u32),
                &PathArgs { time: seconds, target_relmse, ..PathArgs::default() },
                None,
            );
            let mut run = Progressive::create(scene.clone_ref(py), s, width, height, seed, stop.spp, max_depth).py_err()?;
            run.run(py, stop, &report)?;
            run.image(py)
        }
        other => bad(format!("integrator={other:?}: \"path\" or \"whitted\"")),
    }
}

/// `vkrt.resume`: a run saved by `Progressive.save` or `vkrt render --checkpoint`, with its
/// scene loaded as it was (file, sky, camera, builder, layout) on `device`.
#[pyfunction]
#[pyo3(signature = (checkpoint, device=None))]
pub fn _resume(py: Python<'_>, checkpoint: PathBuf, device: Option<String>) -> PyResult<Progressive> {
    let c = py.allow_threads(|| Checkpoint::read(&checkpoint)).py_err()?;
    let stored = &c.settings;
    if stored.shards.is_some() {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{}: a shard of a sharded run: merge the shards first (vkrt.merge)",
            checkpoint.display()
        )));
    }
    let Identity::Inputs { sky, camera, .. } = &stored.identity else {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{}: written by an older vkrt that did not record its sky and camera; resume it with `vkrt render --resume`",
            checkpoint.display()
        )));
    };
    let cam = vkrt::cli::render::camera_from(camera);
    // The command line's resume: the stored sky and camera, unless replaced (here never).
    let mut view = crate::scene::View { stored_sky: Some(sky.clone()), ..crate::scene::View::default() };
    view.camera.eye = Some(cam.eye);
    view.camera.target = Some(cam.target);
    view.camera.up = Some(cam.up);
    view.camera.fov = Some(cam.fov_y_deg);
    view.camera.aperture = Some(cam.lens.aperture_radius);
    view.camera.focus_distance = Some(cam.lens.focus_distance);
    let scene_path = PathBuf::from(&stored.scene_path);
    let (builder, layout) = (stored.resume.builder.clone(), stored.resume.layout.clone());
    let scene = py
        .allow_threads(|| {
            let (builder, layout) = (Some(builder.as_str()).filter(|s| !s.is_empty()), Some(layout.as_str()).filter(|s| !s.is_empty()));
            Scene::load(&scene_path, &view, builder, layout, true, device.as_deref())
        })
        .py_err()?;
    let scene = Py::new(py, scene)?;
    let s = scene.bind(py).get();
    let image = image_settings(s, stored.width, stored.height, stored.seeds.first().copied().unwrap_or(0), IntegratorKind::Path).py_err()?;
    let stop = Stop { spp: stored.resume.spp, seconds: stored.resume.seconds, target_relmse: stored.resume.target_relmse };
    let settings = render_path::path_settings(&PathArgs::default(), image, None, Some(stored), stop);
    let mut run = Progressive { scene: scene.clone_ref(py), settings, seed: image.seed, acc: None, planned: stored.resume.spp, seconds: 0.0, rays: 0 };
    let ours = run.run_settings(s).py_err()?;
    let path_run = run.path_run(s, stored.scene_path.clone());
    let acc = render_path::resumed_sums(&c, &checkpoint, &path_run, &ours, &|_| {}).py_err()?;
    run.acc = Some(acc);
    Ok(run)
}

/// `vkrt.merge`: checkpoints of runs with different seeds, or every shard of one run, added
/// into one; returns the image and writes `output` (an image or a `.ckpt`) if given.
#[pyfunction]
#[pyo3(signature = (checkpoints, output=None))]
pub fn _merge<'py>(py: Python<'py>, checkpoints: Vec<PathBuf>, output: Option<PathBuf>) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let image = py
        .allow_threads(|| -> Result<Image> {
            let merged = vkrt::cli::merge::read_and_merge(&checkpoints)?;
            let is_ckpt = output.as_deref().is_some_and(vkrt::cli::merge::is_checkpoint);
            if let Some(missing) = merged.settings.shards.as_ref().and_then(|s| s.missing_message()) {
                if !is_ckpt {
                    bail!("{missing}: the shards given are not the whole run");
                }
            }
            let image = merged.accum.image();
            match &output {
                Some(o) if is_ckpt => merged.write(o)?,
                Some(o) => vkrt::output::write_render(o, &image, &vkrt::output::display::Display::default())?,
                None => {}
            }
            Ok(image)
        })
        .py_err()?;
    to_numpy(py, &image)
}

/// `vkrt.write_image`: see python/vkrt/__init__.py.
#[pyfunction]
#[pyo3(signature = (path, image, exposure=None, tonemap=None))]
pub fn _write_image(py: Python<'_>, path: PathBuf, image: numpy::PyReadonlyArray3<'_, f32>, exposure: Option<String>, tonemap: Option<String>) -> PyResult<()> {
    use clap::ValueEnum as _;
    use numpy::PyUntypedArrayMethods as _;
    let bad = |m: String| Err(pyo3::exceptions::PyValueError::new_err(m));
    let shape = image.shape().to_vec();
    let [height, width, 3] = shape[..] else { return bad(format!("the image must have shape (height, width, 3), not {shape:?}")) };
    let (Ok(w), Ok(h)) = (u32::try_from(width), u32::try_from(height)) else { return bad(format!("image size {width}x{height} is too large")) };
    if w == 0 || h == 0 {
        return bad(format!("image size {width}x{height} is empty"));
    }
    // The command line's parsers, so that the same words mean the same.
    let exposure = match exposure {
        None => Default::default(),
        Some(e) => match vkrt::cli::args::exposure(&e) {
            Ok(e) => e,
            Err(m) => return bad(format!("exposure={e:?}: {m}")),
        },
    };
    let tonemap = match tonemap {
        None => Default::default(),
        Some(t) => match vkrt::output::display::Tonemap::from_str(&t, true) {
            Ok(t) => t,
            Err(m) => return bad(format!("tonemap={t:?}: {m}")),
        },
    };
    let a = image.as_array();
    let pixels = (0..h as usize).flat_map(|y| (0..w as usize).map(move |x| (y, x))).map(|(y, x)| [a[[y, x, 0]], a[[y, x, 1]], a[[y, x, 2]]]).collect();
    let image = Image { width: w, height: h, pixels };
    let display = vkrt::output::display::Display { exposure, tonemap };
    py.allow_threads(|| vkrt::output::write_render(&path, &image, &display)).py_err()
}
