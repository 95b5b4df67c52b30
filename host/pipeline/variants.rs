// The shaders and how each is built: host/build.rs includes this file (with
// host/accel/kinds.rs) and compiles one SPIR-V per variant; `crate::pipeline::shaders` loads
// the embedded ones. Nothing here imports the crate, so build.rs can include it on its own.
//
// Compile-time feature switches are `-D` defines (here); numeric knobs are specialization
// constants; per-dispatch values are push constants (`GpuPush`).

/// Who a shader is for, which decides where its SPIR-V goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// Embedded in the library and the `vkrt` binary.
    Product,
    /// Embedded only with the `bench` cargo feature (the tools crate turns it on): baselines
    /// that benchmarks measure the product against.
    Bench,
    /// Test probes: written to `$OUT_DIR/probes/NAME.spv` for the tests, never embedded.
    Probe,
}

/// One shader source and how to build it.
pub struct Shader {
    /// Variant name; a shader built per layout gets `_<layout id>` appended (`path_wide`).
    pub name: &'static str,
    /// Source file under `shaders/`.
    pub source: &'static str,
    /// Preprocessor defines (`NAME` or `NAME=VALUE`).
    pub defines: &'static [&'static str],
    /// Built once per BVH layout of `accel::kinds::LAYOUTS`, each with that layout's define,
    /// and (a product shader) once more per two-level walk as `<name>_two_level_<id>` with
    /// `TWO_LEVEL` and that layout's define, for the two-level BVH of a scene with instances
    /// (`accel::two_level`; `LayoutInfo::two_level` says which build walks which levels);
    /// otherwise built once, walking the threaded layout if it traces at all.
    pub per_layout: bool,
    pub role: Role,
}

pub const SHADERS: &[Shader] = &[
    // The integrators trace through alpha cut-outs (shaders/include/leaf.glsl).
    Shader { name: "whitted", source: "whitted.comp", defines: &["ALPHA_TEST"], per_layout: true, role: Role::Product },
    Shader { name: "path", source: "path.comp", defines: &["ALPHA_TEST", "STOCHASTIC_ALPHA"], per_layout: true, role: Role::Product },
    // The same with what the path tracer does for mirrors (the probe pass, mirror_probe.glsl,
    // and light through planar mirrors, mirror_light.glsl), for scenes with mirror materials:
    // in `path` that code would cost every other scene ~16 ms of pipeline creation on
    // lavapipe (SPIR-V is parsed before specialization constants can drop code).
    Shader { name: "path_mirrors", source: "path.comp", defines: &["ALPHA_TEST", "STOCHASTIC_ALPHA", "MIRRORS"], per_layout: true, role: Role::Product },
    // The same two with diffuse bounces aimed at caustic casters (caster_guide.glsl), for scenes
    // with casters (prepare::casters): in `path` that code cost every other scene ~25 ms of
    // pipeline creation (0.092 -> 0.12 s for a 16² 1-spp render, median of 6). They never make
    // light-vertex connections, so CASTERS also compiles that code out (light_connection.glsl).
    Shader { name: "path_casters", source: "path.comp", defines: &["ALPHA_TEST", "STOCHASTIC_ALPHA", "CASTERS"], per_layout: true, role: Role::Product },
    Shader {
        name: "path_mirrors_casters",
        source: "path.comp",
        defines: &["ALPHA_TEST", "STOCHASTIC_ALPHA", "MIRRORS", "CASTERS"],
        per_layout: true,
        role: Role::Product,
    },
    // The four above, lean: every feature but mirrors, glossy lobes and emissive triangles
    // compiled out (`prepare::Features::lean`; shaders/include/features.glsl), for scenes that
    // use no other. Lavapipe parses the SPIR-V before specialization drops dead code: on the
    // Cornell boxes pipeline creation 20-50 ms shorter (docs/experiments/lean-variants.md).
    Shader { name: "path_lean", source: "path.comp", defines: &["LEAN"], per_layout: true, role: Role::Product },
    Shader { name: "path_mirrors_lean", source: "path.comp", defines: &["LEAN", "MIRRORS"], per_layout: true, role: Role::Product },
    Shader { name: "path_casters_lean", source: "path.comp", defines: &["LEAN", "CASTERS"], per_layout: true, role: Role::Product },
    Shader { name: "path_mirrors_casters_lean", source: "path.comp", defines: &["LEAN", "MIRRORS", "CASTERS"], per_layout: true, role: Role::Product },
    // Batch ray queries see geometry only.
    Shader { name: "trace", source: "trace.comp", defines: &[], per_layout: true, role: Role::Product },
    // The textbook intersection tests, only to measure what the robust ones cost
    // (tools/bench: vkrt-robust-cost).
    Shader { name: "trace_plain", source: "trace.comp", defines: &["PLAIN_INTERSECT"], per_layout: false, role: Role::Bench },
    Shader { name: "layout_probe", source: "test/layout_probe.comp", defines: &[], per_layout: true, role: Role::Probe },
    Shader { name: "texel_decode_probe", source: "test/texel_decode_probe.comp", defines: &[], per_layout: true, role: Role::Probe },
    Shader { name: "bsdf_probe", source: "test/bsdf_probe.comp", defines: &[], per_layout: false, role: Role::Probe },
    Shader { name: "sampler_probe", source: "test/sampler_probe.comp", defines: &[], per_layout: false, role: Role::Probe },
    Shader { name: "division_probe", source: "test/division_probe.comp", defines: &[], per_layout: false, role: Role::Probe },
];
