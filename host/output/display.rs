//! From scene-referred radiance to an 8-bit picture: exposure, then a display transform, then
//! the sRGB encoding (`image::linear_to_srgb`). Only 8-bit outputs (PNG) go through it; float
//! outputs (EXR, PFM) stay linear and scene-referred, exactly what the integrator computed.

use crate::gpu_abi::luminance;
use crate::integrator::Image;

/// How bright the picture is: radiance is multiplied by 2^EV before the display transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Exposure {
    /// Exposure value in stops (0: the radiance as it is).
    Ev(f32),
    /// The EV that maps the image's log-average luminance to middle grey 0.18 (Reinhard et al.
    /// 2002, "Photographic tone reproduction for digital images", the "key" of the scene), but
    /// never so bright that the 95th percentile of luminance passes 1 ([`HIGHLIGHT_PERCENTILE`]).
    Auto,
}

/// The default is `Auto`: on the course scenes and the McGuire boxes EV 0 ranges from blown
/// out (Box_ver_path, 41 % of values above 1) to nearly black (CornellBox-Sphere, mean 0.003),
/// and the automatic key puts all of them within 0.07-0.3 of mean display value with at most
/// 5.5 % of pixels saturated after PBR Neutral (docs/experiments/display-transform.md).
impl Default for Exposure {
    fn default() -> Self {
        Exposure::Auto
    }
}

/// The display transform for 8-bit outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Tonemap {
    /// Khronos PBR Neutral (2024): linear (after a small toe) up to 0.76, then rolls highlights
    /// off towards 1 and desaturates them a little, so colours below the knee are unchanged
    /// and nothing clips. The default.
    #[default]
    Neutral,
    /// ACES filmic curve, Narkowicz's 2015 fit: a film-like S-curve; darkens mid-tones and
    /// shifts saturated highlights toward white.
    Aces,
    /// Clip each channel at 1: exact below 1, blown-out highlights above.
    Clamp,
}

/// Automatic exposure maps this percentile of the lit pixels' luminance to at most 1
/// (docs/experiments/display-transform.md, "Highlights").
pub const HIGHLIGHT_PERCENTILE: f64 = 0.95;

impl Exposure {
    /// The scale factor 2^EV for `image`.
    pub fn scale(self, image: &Image) -> f32 {
        match self {
            Exposure::Ev(ev) => ev.exp2(),
            Exposure::Auto => {
                // Over finite pixels; black ones are left out (a black background would
                // otherwise pull the key to zero).
                let mut lit: Vec<f32> = image.pixels.iter().map(|p| luminance(*p)).filter(|l| l.is_finite() && *l > 1e-6).collect();
                if lit.is_empty() {
                    return 1.0;
                }
                let log_sum: f64 = lit.iter().map(|l| f64::from(*l).ln()).sum();
                let key = 0.18 / (log_sum / lit.len() as f64).exp();
                // A small lit object in a dark frame (White Oak's trunk among its shadowed
                // leaves) has a low log-average and would be pushed far past white: the key
                // gives way where the brightest 5 % of pixels would pass 1, above the tone
                // curve's knee, so they keep their detail.
                let k = ((lit.len() - 1) as f64 * HIGHLIGHT_PERCENTILE).floor() as usize;
                let (_, highlight, _) = lit.select_nth_unstable_by(k, f32::total_cmp);
                key.min(1.0 / f64::from(*highlight)) as f32
            }
        }
    }

    /// The EV this exposure applies to `image` (for reports).
    pub fn ev(self, image: &Image) -> f32 {
        self.scale(image).log2()
    }
}

impl Tonemap {
    /// Display-referred linear values in [0, 1] for scene-referred `c` (after exposure).
    pub fn apply(self, c: [f32; 3]) -> [f32; 3] {
        let c = c.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
        match self {
            Tonemap::Clamp => c.map(|x| x.min(1.0)),
            Tonemap::Aces => c.map(|x| ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)),
            Tonemap::Neutral => pbr_neutral(c),
        }
    }
}

/// Khronos PBR Neutral tone mapping (Khronos Group 2024, "PBR Neutral specification").
fn pbr_neutral(mut c: [f32; 3]) -> [f32; 3] {
    const START_COMPRESSION: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let x = c[0].min(c[1]).min(c[2]);
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    c = c.map(|v| v - offset);
    let peak = c[0].max(c[1]).max(c[2]);
    if peak < START_COMPRESSION {
        return c.map(|v| v.clamp(0.0, 1.0));
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    c = c.map(|v| v * new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.map(|v| (v + (new_peak - v) * g).clamp(0.0, 1.0))
}

/// How an image becomes an 8-bit picture.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Display {
    pub exposure: Exposure,
    pub tonemap: Tonemap,
}

impl Display {
    /// What vkrt did before display transforms existed: no exposure, clip at 1.
    pub const CLAMP: Display = Display { exposure: Exposure::Ev(0.0), tonemap: Tonemap::Clamp };

    /// `image` exposed and tone-mapped: linear values in [0, 1], ready for the sRGB encoding.
    pub fn apply(&self, image: &Image) -> Image {
        let scale = self.exposure.scale(image);
        Image { width: image.width, height: image.height, pixels: image.pixels.iter().map(|p| self.tonemap.apply(p.map(|x| x * scale))).collect() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neutral_keeps_the_darks_and_never_clips() {
        // Below the knee the curve is the identity but for its small toe offset.
        let mid = pbr_neutral([0.5, 0.3, 0.2]);
        assert!((mid[0] - 0.46).abs() < 1e-6 && (mid[2] - 0.16).abs() < 1e-6, "{mid:?}");
        // Highlights compress monotonically towards 1 and never reach it.
        let mut last = 0.0;
        for x in [0.8f32, 1.0, 2.0, 8.0, 100.0] {
            let y = pbr_neutral([x; 3])[0];
            assert!(y > last && y < 1.0, "neutral({x}) = {y}");
            last = y;
        }
    }

    #[test]
    fn auto_exposure_maps_the_key_to_middle_grey() {
        let image = Image { width: 2, height: 1, pixels: vec![[2.0; 3], [8.0; 3]] };
        // Log-average 4: scale 0.18 / 4.
        assert!((Exposure::Auto.scale(&image) - 0.045).abs() < 1e-6);
        assert_eq!(Exposure::Ev(2.0).scale(&image), 4.0);
    }

    #[test]
    fn auto_exposure_keeps_a_small_bright_object_below_white() {
        // 90 dark pixels and 10 lit ones: the key alone (log-average 0.01^0.9) would scale by
        // 11.4 and put the lit tenth at 11.4, far past white.
        let mut pixels = vec![[0.01f32; 3]; 90];
        pixels.extend([[1.0f32; 3]; 10]);
        let image = Image { width: 100, height: 1, pixels };
        let scale = Exposure::Auto.scale(&image);
        assert!((scale - 1.0).abs() < 1e-6, "{scale}");
        assert!(pbr_neutral([scale; 3])[0] < 0.9);
        // Where the brightest 5 % are dark enough, the key decides, as before.
        let mut pixels = vec![[0.01f32; 3]; 98];
        pixels.extend([[1.0f32; 3]; 2]);
        let image = Image { width: 100, height: 1, pixels };
        let key = 0.18 / (0.98 * 0.01f64.ln()).exp();
        assert!((f64::from(Exposure::Auto.scale(&image)) - key).abs() < 1e-4 * key);
    }
}
