//! Light-vertex connections: bidirectional path tracing's s = 2 strategy (Veach 1997, "Robust
//! Monte Carlo methods for light transport simulation", chapter 10) inside the path tracer.
//! Each sample also starts one light subpath: a point on an emissive triangle (picked as light
//! sampling picks it), a cosine-distributed direction, and the first surface that ray hits,
//! y1. Every surface vertex x of the camera path is then joined to y1 by one shadow ray. That
//! samples the paths x -> y1 -> light by where the light lands rather than by where x's bounce
//! happens to go, which is what a room lit mostly by interreflection needs (cornell-measured's
//! ceiling, lit only by the floor and walls, held half of its 16-spp error). The three ways of
//! making such a path (x's bounce then light sampling at y1; x's bounce then y1's bounce
//! finding the light; the connection) are weighted by the balance heuristic over their area
//! densities (Veach & Guibas 1995; it gave 4-6 % less relMSE than the power heuristic on
//! cornell-measured with the same rays), so the estimate stays unbiased (`connect_light_vertex` in
//! shaders/include/light_connection.glsl, `next_event` and the emitter hits in
//! shaders/path.comp; docs/experiments/light-connections.md).
//!
//! It costs one closest-hit ray per sample and one shadow ray per camera vertex (1.3-1.8x the
//! time), and pays where diffuse interreflection is most of the error: on cornell-measured and
//! the Lambertian Cornell box half the relMSE per sample, 0.75x the relMSE x seconds, HDR-FLIP
//! -20 %. In the mirror, glass and glossy boxes the error is in paths a connection cannot make
//! or makes badly (light reflected by a mirror, caustics, a glossy y1 seen from a random x), and
//! there it cost more time than it saved (relMSE x seconds 1.2-1.6x). Hence the default.

use super::PathSettings;
use crate::prepare::features::{DIELECTRIC, EMITTERS, GLOSSY, METALLIC_ROUGHNESS, MIRROR};
use crate::prepare::{Features, GpuScene};

/// Whether the path tracer makes light-vertex connections (`--connections`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Connections {
    /// In scenes lit by emissive triangles whose materials are all Lambertian: where they
    /// were measured to pay for their rays.
    #[default]
    Auto,
    /// Wherever there are emissive triangles to start from and light sampling is on, except
    /// in scenes whose diffuse bounces aim at caustic casters (curved mirror, glass or glossy
    /// pieces): that guide's density is not in the connections' weights.
    On,
    /// Never: the plain path tracer with next-event estimation.
    Off,
}

impl Connections {
    /// Whether a run with light sampling `nee` on a scene using `features` connects;
    /// `aims_at_casters`: its bounces aim at caustic casters.
    pub fn resolve(self, features: &Features, nee: bool, aims_at_casters: bool) -> bool {
        if Self::unavailable(features, nee, aims_at_casters).is_some() {
            return false;
        }
        match self {
            Connections::On => true,
            Connections::Off => false,
            Connections::Auto => ![MIRROR, DIELECTRIC, GLOSSY, METALLIC_ROUGHNESS].iter().any(|&f| features.has(f)),
        }
    }

    /// Why a run cannot connect whatever the mode (for the warning `--connections on` gets),
    /// or None.
    pub fn unavailable(features: &Features, nee: bool, aims_at_casters: bool) -> Option<&'static str> {
        if !nee {
            Some("light sampling is off (--no-nee)")
        } else if !features.has(EMITTERS) {
            Some("the scene has no emissive triangles to start light vertices from")
        } else if aims_at_casters {
            Some("its diffuse bounces aim at caustic casters, whose guide the connections' weights leave out")
        } else {
            None
        }
    }
}

/// Whether `settings`' render of `scene` connects: what its pipeline is specialised for and
/// its checkpoints record.
pub fn connects(settings: &PathSettings, scene: &GpuScene) -> bool {
    settings.connections.resolve(&settings.image.features(&scene.info), settings.nee, settings.aims_at_casters(scene))
}

/// Why `settings`' render of `scene` cannot connect whatever its mode, or None.
pub fn unavailable(settings: &PathSettings, scene: &GpuScene) -> Option<&'static str> {
    Connections::unavailable(&settings.image.features(&scene.info), settings.nee, settings.aims_at_casters(scene))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::features::ALL;

    fn features(on: &[crate::prepare::features::Feature]) -> Features {
        Features { entries: ALL.iter().map(|&f| (f, on.contains(&f), String::new())).collect() }
    }

    #[test]
    fn auto_connects_only_lambertian_scenes_lit_by_emitters() {
        assert!(Connections::Auto.resolve(&features(&[EMITTERS]), true, false));
        for other in [MIRROR, DIELECTRIC, GLOSSY, METALLIC_ROUGHNESS] {
            assert!(!Connections::Auto.resolve(&features(&[EMITTERS, other]), true, false), "{other:?}");
            assert!(Connections::On.resolve(&features(&[EMITTERS, other]), true, false), "{other:?}");
        }
        // Nothing to start a light vertex from, no light sampling to weigh against, a guide
        // whose density the weights leave out, or not asked for.
        assert!(!Connections::On.resolve(&features(&[]), true, false));
        assert!(!Connections::On.resolve(&features(&[EMITTERS]), false, false));
        assert!(!Connections::On.resolve(&features(&[EMITTERS, GLOSSY]), true, true));
        assert!(!Connections::Off.resolve(&features(&[EMITTERS]), true, false));
    }
}
