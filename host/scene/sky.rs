//! What rays that leave the scene see: nothing (black), a constant radiance (`--sky R,G,B`), a
//! cube map (lab `Skyboxes`) or an environment map (`--envmap`, `super::envmap`).

use glam::Vec3;

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Sky {
    /// Black: escaping rays carry nothing (the default, as in the seed renderer).
    #[default]
    None,
    /// The same radiance (linear RGB) from every direction.
    Constant(Vec3),
    /// Six faces in `Scene::textures`, starting at `first_texture`, in the order +x, -x, +y, -y,
    /// +z, -z (the lab's `Skyboxes` order and OpenGL's), looked up as an OpenGL cube map;
    /// radiance = face texel^2.2 times `scale`.
    CubeMap { first_texture: u32, scale: Vec3 },
    /// An environment map (`--envmap FILE`; the texels travel beside the scene, as
    /// `prepare::EnvLight`): radiance = texel times `scale`, the map turned by `rotation_deg`
    /// about +y. Unlike the others it is a light: the path tracer samples it.
    Environment { scale: f32, rotation_deg: f32 },
}

impl Sky {
    pub fn is_some(&self) -> bool {
        match *self {
            Sky::None => false,
            Sky::Constant(c) => c.max_element() > 0.0,
            Sky::CubeMap { scale, .. } => scale.max_element() > 0.0,
            Sky::Environment { scale, .. } => scale > 0.0,
        }
    }

    /// Parses `--sky R,G,B`.
    pub fn parse_constant(s: &str) -> anyhow::Result<Sky> {
        let v: Vec<f32> = s
            .split(',')
            .map(|c| c.trim().parse::<f32>().map_err(|e| anyhow::anyhow!("--sky '{s}': '{c}' is not a number ({e})")))
            .collect::<anyhow::Result<_>>()?;
        match v[..] {
            [r, g, b] if v.iter().all(|c| c.is_finite() && *c >= 0.0) => Ok(Sky::Constant(Vec3::new(r, g, b))),
            _ => anyhow::bail!("--sky '{s}': expected three non-negative numbers R,G,B"),
        }
    }
}
