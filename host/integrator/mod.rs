//! Integrators: compute shaders that turn a scene on the GPU into an image.

pub mod accumulation;
pub mod adaptive;
pub mod checkpoint;
pub mod frame;
pub mod gpu_scene;
pub mod light_table;
pub mod path;
pub mod ray_order;
pub mod ray_query;
pub mod tiles;
pub mod whitted;

/// A linear-radiance RGB image, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![[0.0; 3]; (width as usize) * (height as usize)] }
    }
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[(y * self.width + x) as usize]
    }
    /// Mean of each channel.
    pub fn mean(&self) -> [f64; 3] {
        let mut m = [0.0f64; 3];
        for p in &self.pixels {
            for c in 0..3 {
                m[c] += p[c] as f64;
            }
        }
        let n = self.pixels.len().max(1) as f64;
        m.map(|v| v / n)
    }
}

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
    /// Side of the square tiles each submission renders (default 128: on lavapipe a tile of
    /// one sample at depth 7 takes milliseconds, far from any watchdog).
    pub tile_size: u32,
    /// Samples per pixel per submission (default 4).
    pub samples_per_batch: u32,
    /// Run the all-features shader instead of the one specialised to the scene (default false;
    /// for comparisons: both must give the same image).
    pub all_features: bool,
}

impl RenderSettings {
    /// The features the shader is specialised for: the scene's, or all of them.
    pub fn features(&self, scene: &crate::scene::Scene) -> crate::scene::features::Features {
        if self.all_features { crate::scene::features::Features::all() } else { crate::scene::features::Features::of(scene) }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { width: 512, height: 512, spp: 1, max_depth: 7, seed: 0, tile_size: 128, samples_per_batch: 4, all_features: false }
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
    /// The render stopped early because `Hooks::interrupt` was raised (Ctrl-C, SIGTERM).
    pub interrupted: bool,
}
