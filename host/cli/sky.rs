//! The sky a render uses: the scene's own, `--sky R,G,B`, or `--envmap FILE` with its scale and
//! rotation; and the text a checkpoint stores for it, so that a resumed or merged run renders
//! under the same sky ("" for the scene's own, "R,G,B", or "envmap HASH SCALE DEGREES PATH",
//! where HASH is the map file's content hash: a changed map is a different sky).

use crate::prepare::{content_hash, EnvLight};
use crate::scene::envmap::EnvMap;
use crate::scene::{SceneSummary, Sky};
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::{Path, PathBuf};

use super::args::non_negative;

/// The environment-map flags.
#[derive(Debug, Args, Default)]
pub struct EnvmapArgs {
    /// Light the scene with an equirectangular environment map (Radiance .hdr or OpenEXR),
    /// Mitsuba 3's convention: u = atan2(x, -z) / 2pi, v = acos(y) / pi, the top row straight
    /// up. Escaping rays see it; the path tracer samples it as a light. Replaces the scene's
    /// sky and the default light of a file without lights.
    #[arg(help_heading = "Lights", long, value_name = "FILE", conflicts_with = "sky")]
    pub envmap: Option<PathBuf>,
    /// Multiplies the map's radiance [default: 1].
    #[arg(hide = true, long, value_parser = non_negative, value_name = "S", requires = "envmap")]
    pub envmap_scale: Option<f32>,
    /// Turns the map about +y by this many degrees [default: 0].
    #[arg(hide = true, long, value_name = "DEG", allow_negative_numbers = true, requires = "envmap")]
    pub envmap_rotate: Option<f32>,
}

const ENVMAP_PREFIX: &str = "envmap ";

/// The sky text for this run: the command line's, else a resumed run's, else "" (the
/// scene's own).
pub fn sky_text(sky: &Option<String>, env: &EnvmapArgs, stored: Option<String>) -> Result<String> {
    if let Some(path) = &env.envmap {
        let scale = env.envmap_scale.unwrap_or(1.0);
        let degrees = env.envmap_rotate.unwrap_or(0.0);
        if !degrees.is_finite() {
            bail!("--envmap-rotate {degrees}: must be a finite number of degrees");
        }
        let path = std::path::absolute(path).unwrap_or_else(|_| path.clone());
        let hash = content_hash(&path).with_context(|| format!("--envmap {}", path.display()))?;
        return Ok(format!("{ENVMAP_PREFIX}{hash:016x} {scale} {degrees} {}", path.display()));
    }
    Ok(sky.clone().or(stored).unwrap_or_default())
}

/// Sets `scene.sky` from `text` (see [`sky_text`]); for an environment map also loads it and
/// returns it ready for the GPU.
pub fn apply(text: &str, scene: &mut SceneSummary) -> Result<Option<EnvLight>> {
    if text.is_empty() {
        return Ok(None);
    }
    let Some(rest) = text.strip_prefix(ENVMAP_PREFIX) else {
        scene.sky = Sky::parse_constant(text)?;
        return Ok(None);
    };
    let mut parts = rest.splitn(4, ' ');
    let (hash, scale, degrees, path) = match (parts.next(), parts.next(), parts.next(), parts.next()) {
        (Some(h), Some(s), Some(d), Some(p)) => (h, s, d, Path::new(p)),
        _ => bail!("the stored sky '{text}' is not an environment map of this vkrt"),
    };
    let parse = |s: &str| s.parse::<f32>().with_context(|| format!("the stored sky '{text}'"));
    let (scale, degrees) = (parse(scale)?, parse(degrees)?);
    let found = content_hash(path).with_context(|| format!("environment map {}", path.display()))?;
    if format!("{found:016x}") != hash {
        bail!("environment map {} changed since the run began (content hash {found:016x}, was {hash})", path.display());
    }
    let map = EnvMap::load(path)?;
    scene.sky = Sky::Environment { scale, rotation_deg: degrees };
    Ok(Some(EnvLight::new(&map, scale, degrees)))
}
