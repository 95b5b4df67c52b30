//! The compiled SPIR-V of the embedded shader variants (`super::variants::SHADERS`, built by
//! host/build.rs).

use crate::accel::LayoutKind;

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The shaders that trace rays: each is built once per BVH layout, and a pipeline must use the
/// build for the layout of the nodes it walks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tracing {
    Whitted,
    Path(PathShader),
    Trace,
}

/// Which build of the path tracer a render runs (`super::variants::SHADERS`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PathShader {
    /// The mirror probe pass and light through planar mirrors compiled in (scenes with mirror
    /// materials).
    pub mirrors: bool,
    /// Diffuse bounces aimed at caustic casters (scenes with casters).
    pub casters: bool,
    /// Every feature but mirrors, glossy lobes and emissive triangles compiled out
    /// (`prepare::Features::lean`).
    pub lean: bool,
}

impl Tracing {
    /// The SPIR-V of this shader built for `layout`.
    pub fn spirv(self, layout: LayoutKind) -> &'static [u8] {
        let builds = match self {
            Tracing::Whitted => &WHITTED,
            Tracing::Path(p) => match (p.mirrors, p.casters, p.lean) {
                (false, false, false) => &PATH,
                (true, false, false) => &PATH_MIRRORS,
                (false, true, false) => &PATH_CASTERS,
                (true, true, false) => &PATH_MIRRORS_CASTERS,
                (false, false, true) => &PATH_LEAN,
                (true, false, true) => &PATH_MIRRORS_LEAN,
                (false, true, true) => &PATH_CASTERS_LEAN,
                (true, true, true) => &PATH_MIRRORS_CASTERS_LEAN,
            },
            Tracing::Trace => &TRACE,
        };
        builds[layout as usize]
    }

    /// The name of the shader in `super::variants::SHADERS`.
    pub fn name(self) -> &'static str {
        match self {
            Tracing::Whitted => "whitted",
            Tracing::Path(p) => match (p.mirrors, p.casters, p.lean) {
                (false, false, false) => "path",
                (true, false, false) => "path_mirrors",
                (false, true, false) => "path_casters",
                (true, true, false) => "path_mirrors_casters",
                (false, false, true) => "path_lean",
                (true, false, true) => "path_mirrors_lean",
                (false, true, true) => "path_casters_lean",
                (true, true, true) => "path_mirrors_casters_lean",
            },
            Tracing::Trace => "trace",
        }
    }
}

/// SPIR-V words from bytes (copied: `include_bytes!` gives no 4-byte alignment).
pub fn words(spv: &[u8]) -> anyhow::Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(spv)).map_err(|e| anyhow::anyhow!("reading SPIR-V: {e}"))
}
