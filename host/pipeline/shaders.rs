//! The compiled SPIR-V of the embedded shader variants (`super::variants::SHADERS`, built by
//! host/build.rs).

use crate::accel::LayoutKind;

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The shaders that trace rays: each is built once per BVH layout, and a pipeline must use the
/// build for the layout of the nodes it walks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tracing {
    Whitted,
    Path,
    /// The path tracer with the mirror probe pass compiled in (scenes with mirror materials).
    PathMirrors,
    /// The path tracer aiming diffuse bounces at caustic casters (scenes with casters), without
    /// and with the mirror code.
    PathCasters,
    PathMirrorsCasters,
    Trace,
}

impl Tracing {
    /// The SPIR-V of this shader built for `layout`.
    pub fn spirv(self, layout: LayoutKind) -> &'static [u8] {
        let builds = match self {
            Tracing::Whitted => &WHITTED,
            Tracing::Path => &PATH,
            Tracing::PathMirrors => &PATH_MIRRORS,
            Tracing::PathCasters => &PATH_CASTERS,
            Tracing::PathMirrorsCasters => &PATH_MIRRORS_CASTERS,
            Tracing::Trace => &TRACE,
        };
        builds[layout as usize]
    }

    pub fn name(self) -> &'static str {
        match self {
            Tracing::Whitted => "whitted",
            Tracing::Path => "path",
            Tracing::PathMirrors => "path_mirrors",
            Tracing::PathCasters => "path_casters",
            Tracing::PathMirrorsCasters => "path_mirrors_casters",
            Tracing::Trace => "trace",
        }
    }
}

/// SPIR-V words from bytes (copied: `include_bytes!` gives no 4-byte alignment).
pub fn words(spv: &[u8]) -> anyhow::Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(spv)).map_err(|e| anyhow::anyhow!("reading SPIR-V: {e}"))
}
