//! `vkrt rays`: writes one of the comparisons' ray sets (`query::rays`) as an `.npy` file for
//! `vkrt trace`: camera rays through each pixel of the scene's camera, or incoherent rays.

use crate::query::rays;
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RayKind {
    /// One ray through each pixel centre of a WIDTH x HEIGHT image from the scene's camera.
    Primary,
    /// COUNT rays with origins uniform in the scene's bounds and directions uniform on the
    /// sphere (the Embree and tinybvh comparisons' distribution).
    Incoherent,
}

#[derive(Debug, Args)]
pub struct RaysArgs {
    /// Scene file (.obj, lab .yaml, glTF .gltf/.glb).
    pub scene: PathBuf,
    /// Which rays.
    #[arg(long, value_enum)]
    pub kind: RayKind,
    /// Primary rays: image width (COUNT rays: a square image of about COUNT pixels if not given).
    #[arg(long)]
    pub width: Option<u32>,
    /// Primary rays: image height.
    #[arg(long)]
    pub height: Option<u32>,
    /// Number of rays (incoherent; for primary rays the image is made about this many pixels).
    #[arg(long, default_value_t = 1 << 20)]
    pub count: usize,
    /// Seed of the incoherent rays.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Where to write the rays: float32 .npy of shape (N, 8).
    #[arg(short, long, value_name = "RAYS.npy")]
    pub output: PathBuf,
}

pub fn run(args: &RaysArgs) -> Result<()> {
    if args.count == 0 {
        bail!("--count must be at least 1");
    }
    let scene = crate::scene::load_scene(&args.scene)?;
    let made = match args.kind {
        RayKind::Primary => {
            let side = (args.count as f64).sqrt().ceil() as u32;
            let (w, h) = (args.width.unwrap_or(side), args.height.unwrap_or(args.width.unwrap_or(side)));
            if w == 0 || h == 0 {
                bail!("--width and --height must be at least 1");
            }
            rays::primary(&scene, w, h)?
        }
        RayKind::Incoherent => rays::incoherent(&scene, args.count, args.seed),
    };
    crate::output::npy::write_rays(&args.output, &made)?;
    eprintln!("wrote {} {} rays to {}", made.len(), format!("{:?}", args.kind).to_lowercase(), args.output.display());
    Ok(())
}
