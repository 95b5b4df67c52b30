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

// BVH layouts: the unsuffixed variant walks the threaded layout; `_multi_order`,
// `_parent_link`, `_compact` and `_wide` variants (names from `LayoutKind::variant_suffix`) walk the others. A shader
// that traces rays needs one entry per layout to honour `--layout`.
pub const VARIANTS: &[Variant] = &[
    Variant { name: "whitted", source: "whitted.comp", defines: &[] },
    Variant { name: "whitted_multi_order", source: "whitted.comp", defines: &["LAYOUT_MULTI_ORDER"] },
    Variant { name: "whitted_parent_link", source: "whitted.comp", defines: &["LAYOUT_PARENT_LINK"] },
    Variant { name: "whitted_compact", source: "whitted.comp", defines: &["LAYOUT_COMPACT"] },
    Variant { name: "whitted_wide", source: "whitted.comp", defines: &["LAYOUT_WIDE"] },
    Variant { name: "path", source: "path.comp", defines: &[] },
    Variant { name: "path_multi_order", source: "path.comp", defines: &["LAYOUT_MULTI_ORDER"] },
    Variant { name: "path_parent_link", source: "path.comp", defines: &["LAYOUT_PARENT_LINK"] },
    Variant { name: "path_compact", source: "path.comp", defines: &["LAYOUT_COMPACT"] },
    Variant { name: "path_wide", source: "path.comp", defines: &["LAYOUT_WIDE"] },
    Variant { name: "trace", source: "trace.comp", defines: &[] },
    Variant { name: "trace_multi_order", source: "trace.comp", defines: &["LAYOUT_MULTI_ORDER"] },
    Variant { name: "trace_parent_link", source: "trace.comp", defines: &["LAYOUT_PARENT_LINK"] },
    Variant { name: "trace_compact", source: "trace.comp", defines: &["LAYOUT_COMPACT"] },
    Variant { name: "trace_wide", source: "trace.comp", defines: &["LAYOUT_WIDE"] },
    // The textbook intersection tests, only to measure what the robust ones cost.
    Variant { name: "trace_plain", source: "trace.comp", defines: &["PLAIN_INTERSECT"] },
    // Subgroup-coherent walk of the threaded layout (traverse_packet.glsl); an experiment,
    // measured by tools/packet_cost.rs, not used by the integrators.
    Variant { name: "trace_packet", source: "trace.comp", defines: &["PACKET_TRAVERSAL"] },
    Variant { name: "layout_probe", source: "test/layout_probe.comp", defines: &[] },
    Variant { name: "layout_probe_parent_link", source: "test/layout_probe.comp", defines: &["LAYOUT_PARENT_LINK"] },
    Variant { name: "layout_probe_compact", source: "test/layout_probe.comp", defines: &["LAYOUT_COMPACT"] },
    Variant { name: "layout_probe_wide", source: "test/layout_probe.comp", defines: &["LAYOUT_WIDE"] },
    Variant { name: "bsdf_probe", source: "test/bsdf_probe.comp", defines: &[] },
    Variant { name: "sampler_probe", source: "test/sampler_probe.comp", defines: &[] },
    Variant { name: "texel_decode_probe", source: "test/texel_decode_probe.comp", defines: &[] },
    Variant { name: "texel_decode_probe_wide", source: "test/texel_decode_probe.comp", defines: &["LAYOUT_WIDE"] },
];
