//! What an integrator produces: a linear-radiance RGB image.

/// A linear-radiance RGB image, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![[0.0; 3]; (width as usize) * (height as usize)] }
    }
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[(y * self.width + x) as usize]
    }
    /// Mean of each channel.
    pub fn mean(&self) -> [f64; 3] {
        let mut m = [0.0f64; 3];
        for p in &self.pixels {
            for c in 0..3 {
                m[c] += p[c] as f64;
            }
        }
        let n = self.pixels.len().max(1) as f64;
        m.map(|v| v / n)
    }

    /// The mean of each `k` x `k` block of pixels: the image `k` times coarser, as a box pixel
    /// filter would have made it (the size must be a multiple of `k`).
    pub fn box_downsample(&self, k: u32) -> Image {
        let k = k.max(1);
        let (w, h) = (self.width / k, self.height / k);
        let mut out = Image::new(w, h);
        let n = (k * k) as f32;
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0f32; 3];
                for dy in 0..k {
                    for dx in 0..k {
                        let p = self.get(x * k + dx, y * k + dy);
                        for c in 0..3 {
                            sum[c] += p[c];
                        }
                    }
                }
                out.pixels[(y * w + x) as usize] = sum.map(|v| v / n);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::Image;

    #[test]
    fn box_downsampling_averages_blocks() {
        let mut a = Image::new(4, 2);
        for (i, p) in a.pixels.iter_mut().enumerate() {
            *p = [i as f32, 1.0, 0.0];
        }
        let b = a.box_downsample(2);
        assert_eq!((b.width, b.height), (2, 1));
        // Blocks {0, 1, 4, 5} and {2, 3, 6, 7}.
        assert_eq!(b.pixels, vec![[2.5, 1.0, 0.0], [4.5, 1.0, 0.0]]);
    }
}
