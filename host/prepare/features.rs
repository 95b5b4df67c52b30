//! What a scene uses, so that the integrators run a shader with everything else compiled out
//! (specialization constants `SPEC_HAS_*`, shaders/include/features.glsl).

use crate::gpu_abi::constants::*;
use crate::scene::{Light, Material, Scene, Sky};

/// One switchable shader feature: its name, its specialization constant id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Feature {
    pub name: &'static str,
    pub spec_id: u32,
}

pub const TEXTURES: Feature = Feature { name: "textures", spec_id: SPEC_HAS_TEXTURES };
pub const ALPHA: Feature = Feature { name: "alpha cut-outs", spec_id: SPEC_HAS_ALPHA };
pub const DIELECTRIC: Feature = Feature { name: "dielectrics", spec_id: SPEC_HAS_DIELECTRIC };
pub const MIRROR: Feature = Feature { name: "mirrors", spec_id: SPEC_HAS_MIRROR };
pub const GLOSSY: Feature = Feature { name: "glossy lobes", spec_id: SPEC_HAS_GLOSSY };
pub const EMITTERS: Feature = Feature { name: "emissive triangles", spec_id: SPEC_HAS_EMITTERS };
pub const POINT: Feature = Feature { name: "point lights", spec_id: SPEC_HAS_POINT };
pub const DIRECTIONAL: Feature = Feature { name: "directional lights", spec_id: SPEC_HAS_DIRECTIONAL };
pub const SPOT: Feature = Feature { name: "spot lights", spec_id: SPEC_HAS_SPOT };
pub const SKY: Feature = Feature { name: "sky", spec_id: SPEC_HAS_SKY };
pub const ENVMAP: Feature = Feature { name: "environment map", spec_id: SPEC_HAS_ENVMAP };

pub const METALLIC_ROUGHNESS: Feature = Feature { name: "metallic-roughness", spec_id: SPEC_HAS_METALLIC_ROUGHNESS };
pub const NORMAL_MAP: Feature = Feature { name: "normal maps", spec_id: SPEC_HAS_NORMAL_MAP };

pub const CONE: Feature = Feature { name: "cone lights", spec_id: SPEC_HAS_CONE };

pub const ALL: [Feature; 14] =
    [TEXTURES, ALPHA, DIELECTRIC, MIRROR, GLOSSY, EMITTERS, POINT, DIRECTIONAL, SPOT, SKY, ENVMAP, METALLIC_ROUGHNESS, NORMAL_MAP, CONE];

/// The features the lean path tracer keeps as specialization constants; it compiles the rest
/// out (shaders/include/features.glsl, `LEAN`).
pub const LEAN_KEEPS: [Feature; 3] = [MIRROR, GLOSSY, EMITTERS];

/// Which features a scene uses, each with the reason (for `--verbose`).
#[derive(Debug, Clone, PartialEq)]
pub struct Features {
    /// (feature, on, why) for every feature in [`ALL`] order.
    pub entries: Vec<(Feature, bool, String)>,
}

impl Features {
    /// Every feature on: the unspecialised shader, for `--all-features` and comparisons.
    pub fn all() -> Self {
        Self { entries: ALL.iter().map(|&f| (f, true, "forced on (--all-features)".to_string())).collect() }
    }

    /// What `scene` uses. A feature is on if any material that some triangle uses (or any light,
    /// or the sky) needs it; an unused material costs nothing.
    pub fn of(scene: &Scene) -> Self {
        let mut used = vec![false; scene.materials.len()];
        for t in scene.triangles.iter().chain(scene.instances.iter().flat_map(|g| &g.mesh)) {
            if let Some(u) = used.get_mut(t.material as usize) {
                *u = true;
            }
        }
        let mats: Vec<&Material> = scene.materials.iter().zip(&used).filter(|(_, &u)| u).map(|(m, _)| m).collect();
        let named = |pred: &dyn Fn(&Material) -> bool| -> Vec<String> { mats.iter().filter(|m| pred(m)).map(|m| format!("'{}'", m.name)).collect() };
        let why = |names: Vec<String>, what: &str| -> (bool, String) {
            if names.is_empty() {
                (false, format!("no {what}"))
            } else {
                let shown: Vec<String> = names.iter().take(3).cloned().collect();
                let more = if names.len() > 3 { format!(" and {} more", names.len() - 3) } else { String::new() };
                (true, format!("{what}: {}{more}", shown.join(", ")))
            }
        };
        let count_lights = |pred: &dyn Fn(&Light) -> bool, what: &str| -> (bool, String) {
            let n = scene.lights.iter().filter(|l| pred(l)).count();
            if n == 0 {
                (false, format!("no {what}"))
            } else {
                (true, format!("{n} {what}"))
            }
        };
        let entries = vec![
            (TEXTURES, why(named(&|m| m.has_textures()), "materials with a texture")),
            (ALPHA, why(named(&|m| m.alpha_texture.is_some()), "materials with see-through texels")),
            (DIELECTRIC, why(named(&|m| m.is_dielectric()), "dielectric materials")),
            (MIRROR, why(named(&|m| m.is_mirror() && !m.is_dielectric()), "mirror materials")),
            (GLOSSY, why(named(&|m| m.specular.max_element() > 0.0), "materials with Ks > 0")),
            (EMITTERS, why(named(&|m| m.is_emissive()), "emissive materials")),
            (POINT, count_lights(&|l| matches!(l, Light::Point { .. }), "point lights")),
            (DIRECTIONAL, count_lights(&|l| matches!(l, Light::Directional { .. }), "directional lights")),
            (SPOT, count_lights(&|l| matches!(l, Light::Spot { .. }), "spot lights")),
            (SKY, sky_use(&scene.sky)),
            (ENVMAP, envmap_use(&scene.sky)),
            (METALLIC_ROUGHNESS, why(named(&|m| m.metallic_roughness.is_some()), "metallic-roughness materials")),
            (NORMAL_MAP, why(named(&|m| m.normal_texture.is_some()), "materials with a normal map")),
            (CONE, count_lights(&|l| matches!(l, Light::Cone { .. }), "cone (glTF spot) lights")),
        ];
        Self { entries: entries.into_iter().map(|(f, (on, w))| (f, on, w)).collect() }
    }

    /// The same with the sky and environment-map features worked out for `sky` instead
    /// (`--sky` and `--envmap` replace a scene's sky after it was prepared, or loaded from the
    /// cache).
    pub fn with_sky(mut self, sky: &Sky) -> Self {
        for (feature, (on, why)) in [(SKY, sky_use(sky)), (ENVMAP, envmap_use(sky))] {
            for entry in self.entries.iter_mut().filter(|e| e.0 == feature) {
                (entry.1, entry.2) = (on, why.clone());
            }
        }
        self
    }

    /// The same with the light features off, for a scene whose only light is the default one
    /// its loader added (`LoadStats::default_light`, `scene::assemble::light_if_unlit`) when an
    /// environment map replaces it (`GpuScene::set_environment` drops it from the lights): the
    /// shader need not carry code for a light it never meets.
    pub fn without_default_light(mut self) -> Self {
        for entry in self.entries.iter_mut().filter(|e| [POINT, DIRECTIONAL, SPOT, CONE].contains(&e.0)) {
            (entry.1, entry.2) = (false, "the environment map replaces the default light".to_string());
        }
        self
    }

    /// Whether every feature on is one the lean path tracer keeps ([`LEAN_KEEPS`]): then the
    /// render runs the lean build, with the others compiled out (host/pipeline/variants.rs).
    pub fn lean(&self) -> bool {
        self.entries.iter().all(|(f, on, _)| !*on || LEAN_KEEPS.contains(f))
    }

    pub fn has(&self, f: Feature) -> bool {
        self.entries.iter().any(|(g, on, _)| *g == f && *on)
    }

    /// `(constant_id, 0 or 1)` for every feature: the pipeline's specialization constants.
    pub fn spec_constants(&self) -> Vec<(u32, u32)> {
        self.entries.iter().map(|(f, on, _)| (f.spec_id, *on as u32)).collect()
    }

    /// A short name of the variant: the features that are on, or "minimal".
    pub fn variant_name(&self) -> String {
        let on: Vec<&str> = self.entries.iter().filter(|e| e.1).map(|e| e.0.name).collect();
        if on.len() == ALL.len() {
            "all features".into()
        } else if on.is_empty() {
            "minimal".into()
        } else {
            on.join(" + ")
        }
    }

    /// One line per feature: on/off and why, for `--verbose`.
    pub fn report(&self) -> String {
        self.entries.iter().map(|(f, on, w)| format!("  {:<20} {:<3} ({w})\n", f.name, if *on { "on" } else { "off" })).collect()
    }
}

/// Whether a sky needs the sky code, and why.
fn sky_use(sky: &Sky) -> (bool, String) {
    match sky {
        Sky::None => (false, "no sky".to_string()),
        Sky::Constant(c) if c.max_element() <= 0.0 => (false, "black sky".to_string()),
        Sky::Constant(c) => (true, format!("constant sky {c}")),
        Sky::CubeMap { .. } => (true, "cube-map sky box".to_string()),
        Sky::Environment { .. } => (false, "an environment map instead".to_string()),
    }
}

/// Whether the sky is an environment map (looked up and, in the path tracer, sampled as a light).
fn envmap_use(sky: &Sky) -> (bool, String) {
    match sky {
        Sky::Environment { scale, rotation_deg } if *scale > 0.0 => (true, format!("--envmap, scale {scale}, turned {rotation_deg} degrees")),
        Sky::Environment { .. } => (false, "environment map of scale 0".to_string()),
        _ => (false, "no environment map".to_string()),
    }
}
