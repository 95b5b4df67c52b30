// The table of shader variants: one `.spv` per entry, compiled by `host/build.rs` (which
// includes this file) and loaded by name through `crate::pipeline::shaders`.
//
// Compile-time feature switches are `-D` defines here; numeric knobs are specialization
// constants; per-dispatch values are push constants (`GpuPush`).

/// One compiled shader.
pub struct Variant {
    /// Name of the `.spv` and of the generated `pipeline::shaders::NAME` constant (upper-cased).
    pub name: &'static str,
    /// Source file under `shaders/`.
    pub source: &'static str,
    /// Preprocessor defines (`NAME` or `NAME=VALUE`).
    pub defines: &'static [&'static str],
}

pub const VARIANTS: &[Variant] = &[
    Variant { name: "whitted", source: "whitted.comp", defines: &[] },
    Variant { name: "path", source: "path.comp", defines: &[] },
    Variant { name: "trace", source: "trace.comp", defines: &[] },
    Variant { name: "layout_probe", source: "test/layout_probe.comp", defines: &[] },
    Variant { name: "bsdf_probe", source: "test/bsdf_probe.comp", defines: &[] },
];
