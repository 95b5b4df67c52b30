//! Test scenes written as OBJ text, and the noise of renders compared seed against seed.

use vkrt::integrator::Image;

/// `obj` and `mtl` written as `box.obj` and `box.mtl` into the scratch folder `name` (one per
/// test: tests run in parallel) and loaded.
pub fn load_obj_text(name: &str, obj: &str, mtl: &str) -> vkrt::scene::Scene {
    let dir = super::scratch_dir(name);
    std::fs::write(dir.join("box.mtl"), mtl).unwrap();
    std::fs::write(dir.join("box.obj"), obj).unwrap();
    vkrt::scene::load_scene(&dir.join("box.obj")).unwrap()
}

/// The mean of pixel (x, y)'s channels.
pub fn luminance(image: &Image, (x, y): (u32, u32)) -> f64 {
    image.get(x, y).iter().map(|&c| f64::from(c)).sum::<f64>() / 3.0
}

/// The noise of one render over `pixels`: the root mean square difference of luminance between
/// two renders with other seeds (the image's own shading cancels out), over sqrt(2).
pub fn noise_over(a: &Image, b: &Image, pixels: impl Iterator<Item = (u32, u32)>) -> f64 {
    let (mut sum, mut n) = (0.0, 0u32);
    for p in pixels {
        sum += (luminance(a, p) - luminance(b, p)).powi(2);
        n += 1;
    }
    (sum / f64::from(n.max(1)) / 2.0).sqrt()
}

/// The same over the whole image.
pub fn image_noise(a: &Image, b: &Image) -> f64 {
    let (w, h) = (a.width, a.height);
    noise_over(a, b, (0..h).flat_map(move |y| (0..w).map(move |x| (x, y))))
}
