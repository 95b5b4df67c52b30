//! Integrators: compute shaders that turn a prepared scene on the GPU (`crate::prepare::GpuScene`)
//! into an image. [`whitted`] renders in one pass of tiles; [`path`] renders progressively, in
//! short batches of samples, until a stop rule holds. Both dispatch through [`tiles`] and read
//! the frame uniform [`frame`] makes.

pub mod frame;
pub mod image;
pub mod path;
pub mod tiles;
pub mod whitted;

pub use image::Image;

/// Settings shared by the integrators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel; 1 samples each pixel centre, more are jittered inside the pixel.
    pub spp: u32,
    /// Rays per path: 1 is primary rays only (default 7).
    pub max_depth: u32,
    pub seed: u32,
    /// Side of the square tiles each submission renders; 0 (the default): the device's
    /// (`gpu::Workgroups::tile`). Images do not depend on it (tests/memory_models.rs).
    pub tile_size: u32,
    /// Samples per pixel per submission (default 4).
    pub samples_per_batch: u32,
    /// Run the all-features shader instead of the one specialised to the scene (default false;
    /// for comparisons: both must give the same image).
    pub all_features: bool,
}

impl RenderSettings {
    /// The features the shader is specialised for: the scene's, or all of them.
    pub fn features(&self, scene: &crate::prepare::SceneInfo) -> crate::prepare::Features {
        if self.all_features {
            crate::prepare::Features::all()
        } else {
            scene.features.clone()
        }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { width: 512, height: 512, spp: 1, max_depth: 7, seed: 0, tile_size: 0, samples_per_batch: 4, all_features: false }
    }
}

/// What a render reports besides the image.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderStats {
    /// Samples that came out NaN or infinite and were left out of the image.
    pub nonfinite_samples: u64,
    /// Submissions made.
    pub submissions: u32,
    pub seconds: f64,
    /// Of `seconds`: creating the compute pipeline (`ComputePipeline::creation_seconds`),
    /// 30-120 ms on lavapipe per variant: a fixed cost that `render -v` shows beside the total.
    pub pipeline_seconds: f64,
    /// Path tracer: error estimates made (each a read-back of the sums and a pass over them),
    /// and the seconds they took, also part of `seconds`.
    pub estimates: u32,
    pub estimate_seconds: f64,
    /// The render stopped early because `Hooks::interrupt` was raised (Ctrl-C, SIGTERM).
    pub interrupted: bool,
    /// Path tracer: light-vertex connections were on (`path::connections`).
    pub light_connections: bool,
    /// The shader build the render ran (`pipeline::variants::SHADERS`, without the layout).
    pub shader: &'static str,
    /// Where its compiled form came from (`ComputePipeline::origin`, as words).
    pub shader_origin: String,
    /// Path tracer: rays this run traced (closest-hit and shadow rays, the shader's per-pixel
    /// counts summed); 0 for Whitted. A measure of a render's work that, unlike its time, does
    /// not move with the machine's load.
    pub rays: u64,
}
