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
    /// (`prepare::Features::lean`); with `mirrors`, light-vertex connections too
    /// ([`PathShader::can_connect`]).
    pub lean: bool,
}

impl PathShader {
    /// Whether this build has the light-vertex connections' code: the builds aiming at casters
    /// (which never connect) and the lean mirror builds leave it out, by the same condition in
    /// shaders/include/light_connection.glsl.
    pub fn can_connect(self) -> bool {
        !(self.casters || (self.mirrors && self.lean))
    }
}

impl Tracing {
    /// The SPIR-V of this shader built for `layout`.
    pub fn spirv(self, layout: LayoutKind) -> &'static [u8] {
        self.builds().1[layout as usize]
    }

    /// The SPIR-V of this shader built for a two-level BVH (`accel::two_level`) laid out in
    /// `layout`; None for a layout no two-level BVH is laid out in.
    pub fn spirv_two_level(self, layout: LayoutKind) -> Option<&'static [u8]> {
        let builds = match self {
            Tracing::Whitted => &WHITTED_TWO_LEVEL,
            Tracing::Path(p) => match (p.mirrors, p.casters, p.lean) {
                (false, false, false) => &PATH_TWO_LEVEL,
                (true, false, false) => &PATH_MIRRORS_TWO_LEVEL,
                (false, true, false) => &PATH_CASTERS_TWO_LEVEL,
                (true, true, false) => &PATH_MIRRORS_CASTERS_TWO_LEVEL,
                (false, false, true) => &PATH_LEAN_TWO_LEVEL,
                (true, false, true) => &PATH_MIRRORS_LEAN_TWO_LEVEL,
                (false, true, true) => &PATH_CASTERS_LEAN_TWO_LEVEL,
                (true, true, true) => &PATH_MIRRORS_CASTERS_LEAN_TWO_LEVEL,
            },
            Tracing::Trace => &TRACE_TWO_LEVEL,
        };
        builds[layout as usize]
    }

    /// The name of the shader in `super::variants::SHADERS`.
    pub fn name(self) -> &'static str {
        self.builds().0
    }

    /// The name and the per-layout builds, from one table.
    fn builds(self) -> (&'static str, &'static [&'static [u8]; LayoutKind::ALL.len()]) {
        match self {
            Tracing::Whitted => ("whitted", &WHITTED),
            Tracing::Path(p) => match (p.mirrors, p.casters, p.lean) {
                (false, false, false) => ("path", &PATH),
                (true, false, false) => ("path_mirrors", &PATH_MIRRORS),
                (false, true, false) => ("path_casters", &PATH_CASTERS),
                (true, true, false) => ("path_mirrors_casters", &PATH_MIRRORS_CASTERS),
                (false, false, true) => ("path_lean", &PATH_LEAN),
                (true, false, true) => ("path_mirrors_lean", &PATH_MIRRORS_LEAN),
                (false, true, true) => ("path_casters_lean", &PATH_CASTERS_LEAN),
                (true, true, true) => ("path_mirrors_casters_lean", &PATH_MIRRORS_CASTERS_LEAN),
            },
            Tracing::Trace => ("trace", &TRACE),
        }
    }
}

/// SPIR-V words from bytes (copied: `include_bytes!` gives no 4-byte alignment).
pub fn words(spv: &[u8]) -> anyhow::Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(spv)).map_err(|e| anyhow::anyhow!("reading SPIR-V: {e}"))
}
