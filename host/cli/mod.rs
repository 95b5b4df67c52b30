//! The `vkrt` command line: one file per command. Each parses its flags (clap), runs the
//! pipeline scene -> prepare -> integrator or query, and writes its output in one place.

pub mod args;
pub mod bvh;
pub mod compare;
pub mod info;
pub mod interrupt;
pub mod merge;
pub mod progress;
pub mod rays;
pub mod render;
pub mod render_path;
pub mod shard;
pub mod sky;
pub mod trace;

use crate::accel::LayoutKind;
use crate::gpu::{Context, ContextOptions};
use anyhow::Result;
use clap::{Args, Parser, Subcommand};

/// The BVH walk a command's report names: the layout, or for a two-level BVH of `instances`
/// instances (`accel::two_level`: a tree per mesh under a top level) that of its levels.
pub fn walk_name(layout: LayoutKind, instances: usize) -> String {
    match instances {
        0 => layout.name().to_string(),
        n => format!("two-level {} ({n} instances)", layout.name()),
    }
}

/// vkrt: a GPU-agnostic ray and path tracer on Vulkan compute shaders.
///
/// Runs headless on any Vulkan 1.2 device, including Mesa's lavapipe on a machine with no GPU.
#[derive(Debug, Parser)]
#[command(name = "vkrt", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// What `vkrt render --help` ends with: where the flags it leaves out are.
const RENDER_AFTER_HELP: &str = "More flags (the seed, the camera's up and lens, the map's scale and turn, and the knobs for \
experiments: sampler, coherence, connections, batch size, BVH builder and layout): vkrt render --help-expert";

/// The flag that shows `vkrt render`'s whole help, hidden flags included.
pub const HELP_EXPERT: &str = "--help-expert";

/// `vkrt render --help-expert`: the render command's long help with every flag, those that
/// `--help` leaves out included (they work either way).
pub fn render_help_expert() -> String {
    use clap::CommandFactory;
    let mut cli = Cli::command();
    let Some(render) = cli.find_subcommand_mut("render") else { return String::new() };
    let all = render.clone().bin_name("vkrt render").mut_args(|a| a.hide(false)).after_help("");
    all.clone().render_long_help().to_string()
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene (.obj, lab .yaml, glTF .gltf/.glb) to an image (.png, .exr or .pfm).
    #[command(after_help = RENDER_AFTER_HELP)]
    Render(Box<render::RenderArgs>),
    /// List the Vulkan devices and the limits that matter to vkrt.
    Info(DeviceArgs),
    /// Batch ray queries without rendering: rays from an .npy file, hits to an .npy file.
    Trace(trace::TraceArgs),
    /// Write a ray set (camera rays or incoherent rays of a scene) as an .npy file for `trace`.
    Rays(rays::RaysArgs),
    /// Compare every BVH builder x layout on scenes: a table, CSV or JSON, and a heat map.
    Bvh(bvh::BvhArgs),
    /// Add path-traced checkpoints made with different seeds into one image or checkpoint.
    Merge(merge::MergeArgs),
    /// Print RMSE, relMSE, PSNR and per-channel mean differences of an image against a reference.
    Compare(compare::CompareArgs),
}

#[derive(Debug, Args)]
pub struct DeviceArgs {
    /// Vulkan device: an index from `vkrt info` or part of its name. Default: a discrete GPU
    /// if present, else the best other device (lavapipe on a machine without a GPU).
    #[arg(help_heading = "Device", long, env = "VKRT_DEVICE", global = true)]
    pub device: Option<String>,
}

impl DeviceArgs {
    /// A Vulkan context on the chosen device (validation as `VKRT_VALIDATION` says), keeping
    /// compiled shaders in the user's cache folder ([`user_shader_cache`]).
    pub fn context(&self) -> Result<Context> {
        self.context_with_shader_cache(user_shader_cache())
    }

    /// The same, keeping compiled shaders in `shader_cache` (None: nowhere).
    pub fn context_with_shader_cache(&self, shader_cache: Option<std::path::PathBuf>) -> Result<Context> {
        Context::new(&ContextOptions { device: self.device.clone(), shader_cache, ..ContextOptions::from_env() })
    }
}

/// Compiled shaders' folder under a cache folder (the prepared scenes' files sit beside it).
pub fn shader_cache_in(cache_dir: &std::path::Path) -> std::path::PathBuf {
    cache_dir.join("shaders")
}

/// The shader cache in the user's cache folder (`$XDG_CACHE_HOME/vkrt/shaders`, else
/// `~/.cache/vkrt/shaders`), or None when neither variable is set.
pub fn user_shader_cache() -> Option<std::path::PathBuf> {
    crate::prepare::cache::Cache::default_for_user().map(|c| shader_cache_in(&c.dir))
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Trace(args) => trace::run(&args).map(|_| ()),
        Command::Rays(args) => rays::run(&args),
        Command::Bvh(args) => bvh::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Compare(args) => compare::run(&args),
    }
}
