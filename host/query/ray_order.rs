//! The order a batch of rays is traced in. On a SIMD device (lavapipe's 8 lanes, a GPU's warp)
//! the lanes of a subgroup walk the BVH in lockstep, so a subgroup of rays that go different
//! ways runs the union of their walks: on Conference's incoherent rays a subgroup runs 2.2x
//! the node steps and 7x the triangle tests one ray needs (docs/experiments/per-step-cost.md).
//! Sorting such a batch so that neighbouring rays start near each other and point the same
//! way lines the lanes up again (ray reordering: Pharr et al. 1997, "Rendering complex scenes
//! with memory-coherent ray tracing"; Garanzha & Loop 2010, "Fast ray sorting and
//! breadth-first packet traversal for GPU ray tracing", whose key, direction cell then origin
//! cell, this follows). Coherent batches (camera rays in scanline order) are left alone: they
//! are lined up already and the sort would only cost.
//!
//! The order changes nothing but speed: every ray's hit is a function of that ray alone, and
//! the hits go back in the caller's order (tests/ray_order.rs checks it bit for bit).

use crate::geom::morton::spread2;
use crate::gpu_abi::GpuRay;

/// When to reorder a batch before tracing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum RayOrder {
    /// Sort batches that do not look coherent already (judged from a sample of neighbouring
    /// rays: `looks_coherent`).
    #[default]
    Auto,
    /// Trace in the given order.
    Given,
    /// Always sort.
    Sorted,
}

/// Bits per axis of the octahedral direction cell (16 x 16 cells over the sphere).
const DIRECTION_BITS: u32 = 4;
/// Bits per axis of the origin's Morton code, over the batch's origin bounds (16^3 cells).
/// Finer keys sorted no better (docs/experiments/ray-reordering.md), and 20 bits sort in two
/// radix passes.
const ORIGIN_BITS: u32 = 4;
/// Leading key bits two rays must share to count as coherent neighbours: the direction cell
/// and the top two origin levels (4 x 4 x 4 cells of the bounds).
const COHERENT_PREFIX_BITS: u32 = 2 * DIRECTION_BITS + 3 * 2;
/// A batch is coherent when at least this fraction of its neighbouring rays share that prefix.
/// Camera rays in scanline order share it nearly everywhere, rays with random origins and
/// directions nearly nowhere (unit tests below).
const COHERENT_FRACTION: f64 = 0.5;
/// Key width: direction cell above origin cell.
const KEY_BITS: u32 = 2 * DIRECTION_BITS + 3 * ORIGIN_BITS;
const _: () = assert!(KEY_BITS % 2 == 0, "sorted_order sorts two equal digits");

/// Bit i of `x` (below 2^10) moved to bit 3i: one axis of a 3D Morton code.
fn spread3(x: u32) -> u32 {
    let mut x = x & 0x3ff;
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// Cell index in [0, 2^bits) of `x` in [0, 1]; NaN goes to cell 0.
fn cell(x: f32, bits: u32) -> u32 {
    let n = (1u32 << bits) as f32;
    // `as` saturates and maps NaN to 0.
    ((x * n) as u32).min((1 << bits) - 1)
}

/// The direction's cell on the octahedral map of the sphere (equal-ish areas, no seam at the
/// poles), its two coordinates bit-interleaved.
fn direction_cell(d: [f32; 3]) -> u32 {
    let l1 = d[0].abs() + d[1].abs() + d[2].abs();
    let (px, py) = if l1 > 0.0 { (d[0] / l1, d[1] / l1) } else { (0.0, 0.0) };
    let (ox, oy) = if d[2] < 0.0 { ((1.0 - py.abs()).copysign(px), (1.0 - px.abs()).copysign(py)) } else { (px, py) };
    spread2(cell(ox * 0.5 + 0.5, DIRECTION_BITS)) | (spread2(cell(oy * 0.5 + 0.5, DIRECTION_BITS)) << 1)
}

/// Rays per thread below which splitting the host work is not worth a thread.
const RAYS_PER_THREAD: usize = 1 << 16;

/// How many threads host work on `len` rays is split over.
fn threads_for(len: usize) -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get()).min(len / RAYS_PER_THREAD).max(1)
}

/// Runs `f` on matching consecutive parts of `input` and `out` (equal lengths), one thread per
/// part: the host's cores have nothing else to do while the device waits for the batch. One
/// part runs on the calling thread.
pub fn parallel_zip<A: Sync, B: Send>(input: &[A], out: &mut [B], f: impl Fn(&[A], &mut [B]) + Sync) {
    let threads = threads_for(input.len());
    if threads == 1 {
        return f(input, out);
    }
    let part = input.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        for (a, b) in input.chunks(part).zip(out.chunks_mut(part)) {
            scope.spawn(|| f(a, b));
        }
    });
}

/// What a key is relative to: the bounds of the finite origins of some rays.
#[derive(Debug, Clone, Copy)]
struct KeyFrame {
    lo: [f32; 3],
    hi: [f32; 3],
    /// 1 / extent per axis, 0 for a flat or empty axis.
    scale: [f32; 3],
}

impl KeyFrame {
    fn new(lo: [f32; 3], hi: [f32; 3]) -> Self {
        Self { lo, hi, scale: std::array::from_fn(|a| if hi[a] > lo[a] { 1.0 / (hi[a] - lo[a]) } else { 0.0 }) }
    }

    fn of<'r>(rays: impl Iterator<Item = &'r GpuRay>) -> Self {
        let (lo, hi) = rays.fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(mut lo, mut hi), r| {
            for a in 0..3 {
                if r.origin[a].is_finite() {
                    lo[a] = lo[a].min(r.origin[a]);
                    hi[a] = hi[a].max(r.origin[a]);
                }
            }
            (lo, hi)
        });
        Self::new(lo, hi)
    }

    /// Both frames' bounds together.
    fn merge(self, other: Self) -> Self {
        Self::new(std::array::from_fn(|a| self.lo[a].min(other.lo[a])), std::array::from_fn(|a| self.hi[a].max(other.hi[a])))
    }

    /// The ray's key: direction cell, then the origin's Morton code in the frame.
    fn key(&self, r: &GpuRay) -> u32 {
        let axis = |a: usize| spread3(cell((r.origin[a] - self.lo[a]) * self.scale[a], ORIGIN_BITS));
        let morton = (axis(0) << 2) | (axis(1) << 1) | axis(2);
        (direction_cell(r.direction) << (3 * ORIGIN_BITS)) | morton
    }
}

/// The sort key of every ray: direction cell, then the origin's Morton code within the
/// bounds of the batch's finite origins.
pub fn sort_keys(rays: &[GpuRay]) -> Vec<u32> {
    let part = rays.len().div_ceil(threads_for(rays.len())).max(1);
    let frame = std::thread::scope(|scope| {
        let parts: Vec<_> = rays.chunks(part).map(|c| scope.spawn(|| KeyFrame::of(c.iter()))).collect();
        parts.into_iter().filter_map(|h| h.join().ok()).reduce(KeyFrame::merge)
    });
    let Some(frame) = frame else { return Vec::new() };
    let mut keys = vec![0u32; rays.len()];
    parallel_zip(rays, &mut keys, |rays, keys| {
        for (r, k) in rays.iter().zip(keys) {
            *k = frame.key(r);
        }
    });
    keys
}

/// Whether neighbouring keys mostly share their leading [`COHERENT_PREFIX_BITS`].
fn mostly_shared(pairs: impl Iterator<Item = (u32, u32)>) -> bool {
    let shift = KEY_BITS - COHERENT_PREFIX_BITS;
    let (mut shared, mut total) = (0usize, 0usize);
    for (a, b) in pairs {
        shared += usize::from(a >> shift == b >> shift);
        total += 1;
    }
    total == 0 || shared as f64 >= COHERENT_FRACTION * total as f64
}

/// Whether rays with these keys, in this order, are coherent already: most neighbours share
/// the key's leading [`COHERENT_PREFIX_BITS`].
pub fn is_coherent(keys: &[u32]) -> bool {
    mostly_shared(keys.windows(2).map(|w| (w[0], w[1])))
}

/// Neighbour pairs [`looks_coherent`] samples.
const COHERENCE_SAMPLES: usize = 4096;

/// Where the `j`-th neighbour pair [`looks_coherent`] samples starts in a batch of `len` rays:
/// at the fraction {(j + 1/2) / phi} of it (the golden-ratio sequence, Weyl 1916), not at j /
/// pairs: evenly spaced pairs alias with the rows of a camera's rays. A 1024-wide image's 1M
/// rays put all 4096 pairs on five columns, two of them the row's wrap and its middle (where a
/// camera looking down -z crosses the octahedral map's fold), and such a batch (an OBJ's
/// default view of the ladder's dragon) was judged incoherent and sorted: 0.7x the rays/s.
fn sample_start(j: usize, len: usize) -> usize {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    ((((j as f64 + 0.5) * INV_PHI).fract() * (len - 1) as f64) as usize).min(len - 2)
}

/// [`is_coherent`] judged from [`COHERENCE_SAMPLES`] neighbour pairs ([`sample_start`]), in a frame
/// made from those rays only: a coherent batch is traced as it is, so deciding must cost next
/// to nothing (keying a whole million-ray batch takes tens of milliseconds).
pub fn looks_coherent(rays: &[GpuRay]) -> bool {
    if rays.len() < 2 {
        return true;
    }
    let pairs = COHERENCE_SAMPLES.min(rays.len() - 1);
    let at = |j: usize| sample_start(j, rays.len());
    let frame = KeyFrame::of((0..pairs).flat_map(|j| [&rays[at(j)], &rays[at(j) + 1]]));
    mostly_shared((0..pairs).map(|j| (frame.key(&rays[at(j)]), frame.key(&rays[at(j) + 1]))))
}

/// Indices that sort `keys` (below 2^[`KEY_BITS`]) ascending, equal keys in their given order:
/// a least-significant-digit radix sort in two passes of 10 bits, both digit histograms
/// counted in one read of the keys; the first pass moves (high digit, index) pairs, the second
/// writes the indices.
pub fn sorted_order(keys: &[u32]) -> Vec<u32> {
    const DIGIT: u32 = KEY_BITS / 2;
    const BUCKETS: usize = 1 << DIGIT;
    const MASK: u32 = (1 << DIGIT) - 1;
    let mut low = vec![0usize; BUCKETS + 1];
    let mut high = vec![0usize; BUCKETS + 1];
    for &k in keys {
        low[(k & MASK) as usize + 1] += 1;
        high[((k >> DIGIT) & MASK) as usize + 1] += 1;
    }
    for b in 0..BUCKETS {
        low[b + 1] += low[b];
        high[b + 1] += high[b];
    }
    let mut by_low = vec![0u64; keys.len()];
    for (i, &k) in keys.iter().enumerate() {
        let slot = &mut low[(k & MASK) as usize];
        by_low[*slot] = (u64::from((k >> DIGIT) & MASK) << 32) | i as u64;
        *slot += 1;
    }
    let mut order = vec![0u32; keys.len()];
    for &p in &by_low {
        let slot = &mut high[(p >> 32) as usize];
        order[*slot] = p as u32;
        *slot += 1;
    }
    order
}

/// The order to trace `rays` in under `policy`: None for the given order, else the indices
/// of the rays in tracing order.
pub fn plan(rays: &[GpuRay], policy: RayOrder) -> Option<Vec<u32>> {
    if policy == RayOrder::Given || rays.len() < 2 || (policy == RayOrder::Auto && looks_coherent(rays)) {
        return None;
    }
    Some(sorted_order(&sort_keys(rays)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> GpuRay {
        GpuRay { origin: o, tmin: 0.0, direction: d, tmax: f32::INFINITY }
    }

    fn random_rays(n: usize) -> Vec<GpuRay> {
        let mut rng = crate::rng::Pcg32::new(7);
        (0..n)
            .map(|_| {
                let o = [rng.f32() * 10.0, rng.f32() * 10.0, rng.f32() * 10.0];
                let d = [rng.f32() * 2.0 - 1.0, rng.f32() * 2.0 - 1.0, rng.f32() * 2.0 - 1.0];
                ray(o, d)
            })
            .collect()
    }

    fn camera_rays(w: usize, h: usize) -> Vec<GpuRay> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 / w as f32 - 0.5, (i / w) as f32 / h as f32 - 0.5);
                ray([1.0, 2.0, 3.0], [x, y, 1.0])
            })
            .collect()
    }

    #[test]
    fn morton_spreads_match_the_definition() {
        let spread = |x: u32, bits: u32, stride: u32| (0..bits).fold(0, |acc, i| acc | (((x >> i) & 1) << (stride * i)));
        for x in 0..1024 {
            assert_eq!(spread3(x), spread(x, 10, 3), "spread3({x})");
        }
        for x in (0..65536).step_by(7) {
            assert_eq!(spread2(x), spread(x, 16, 2), "spread2({x})");
        }
    }

    #[test]
    fn radix_order_sorts_stably() {
        let keys: Vec<u32> = random_rays(5000).iter().map(|r| (r.origin[0] * 1e5) as u32 % (1 << KEY_BITS)).collect();
        let keys: Vec<u32> = keys.iter().map(|k| k & !0xff).collect(); // many ties
        let order = sorted_order(&keys);
        let mut seen = vec![false; keys.len()];
        for &i in &order {
            assert!(!seen[i as usize], "index {i} twice");
            seen[i as usize] = true;
        }
        for w in order.windows(2) {
            let (a, b) = (w[0] as usize, w[1] as usize);
            assert!(keys[a] < keys[b] || (keys[a] == keys[b] && a < b), "{a} before {b}: keys {} {}", keys[a], keys[b]);
        }
    }

    #[test]
    fn keys_put_direction_first_and_stay_in_range() {
        let rays = random_rays(2000);
        let keys = sort_keys(&rays);
        assert!(keys.iter().all(|&k| k < 1 << KEY_BITS));
        // Same direction, different origins: same direction cell, so the same top bits.
        let a = sort_keys(&[ray([0.0; 3], [0.3, -0.2, 0.9]), ray([5.0; 3], [0.3, -0.2, 0.9]), ray([9.0, 0.0, 1.0], [0.3, -0.2, 0.9])]);
        assert!(a.iter().all(|&k| k >> (3 * ORIGIN_BITS) == a[0] >> (3 * ORIGIN_BITS)));
        assert!(a[0] != a[1] && a[1] != a[2], "different origin cells, different keys: {a:?}");
        // Opposite directions never share a cell.
        let b = sort_keys(&[ray([0.0; 3], [0.3, -0.2, 0.9]), ray([0.0; 3], [-0.3, 0.2, -0.9])]);
        assert_ne!(b[0] >> (3 * ORIGIN_BITS), b[1] >> (3 * ORIGIN_BITS));
    }

    #[test]
    fn coherence_tells_camera_rays_from_random_ones() {
        assert!(is_coherent(&sort_keys(&camera_rays(256, 128))), "scanline camera rays are coherent");
        assert!(!is_coherent(&sort_keys(&random_rays(20000))), "random rays are not");
        assert!(looks_coherent(&camera_rays(256, 128)), "sampled: camera rays");
        assert!(!looks_coherent(&random_rays(20000)), "sampled: random rays");
        // The sample sees what the whole batch shows: camera rays with every other one replaced
        // by a random ray are not coherent.
        let mixed: Vec<GpuRay> =
            camera_rays(256, 128).into_iter().zip(random_rays(256 * 128)).enumerate().map(|(i, (c, r))| if i % 2 == 0 { c } else { r }).collect();
        assert!(!is_coherent(&sort_keys(&mixed)) && !looks_coherent(&mixed));
        assert!(plan(&camera_rays(64, 64), RayOrder::Auto).is_none());
        assert!(plan(&random_rays(1000), RayOrder::Auto).is_some());
        assert!(plan(&random_rays(1000), RayOrder::Given).is_none());
        assert!(plan(&camera_rays(64, 64), RayOrder::Sorted).is_some());
    }

    #[test]
    fn the_sample_does_not_alias_with_image_rows() {
        // 1M camera rays of a 1024-wide image: the pairs start in hundreds of columns, never at
        // the batch's last ray (a pair needs the ray after it).
        let (len, width) = (1024 * 1024, 1024);
        let starts: Vec<usize> = (0..COHERENCE_SAMPLES).map(|j| sample_start(j, len)).collect();
        let columns: std::collections::HashSet<usize> = starts.iter().map(|s| s % width).collect();
        assert!(columns.len() > width / 2, "{} columns", columns.len());
        assert!(starts.iter().all(|&s| s + 1 < len));
        assert_eq!(sample_start(0, 2), 0);
    }

    #[test]
    fn sorting_groups_alike_rays() {
        // 50k random rays over 256 direction cells: after sorting, nearly all neighbours share
        // their direction cell; before, ~1 in 256.
        let rays = random_rays(50000);
        let keys = sort_keys(&rays);
        let sorted: Vec<u32> = sorted_order(&keys).iter().map(|&i| keys[i as usize]).collect();
        let same_direction = |k: &[u32]| k.windows(2).filter(|w| w[0] >> (3 * ORIGIN_BITS) == w[1] >> (3 * ORIGIN_BITS)).count() as f64 / (k.len() - 1) as f64;
        assert!(same_direction(&keys) < 0.01, "{}", same_direction(&keys));
        assert!(same_direction(&sorted) > 0.9, "{}", same_direction(&sorted));
    }

    #[test]
    fn frames_merge_like_one_frame() {
        let rays = random_rays(300);
        let whole = KeyFrame::of(rays.iter());
        let nan = [ray([f32::NAN; 3], [0.0, 0.0, 1.0])];
        let merged = KeyFrame::of(rays[..100].iter()).merge(KeyFrame::of(nan.iter())).merge(KeyFrame::of(rays[100..].iter()));
        assert_eq!((whole.lo, whole.hi, whole.scale), (merged.lo, merged.hi, merged.scale));
    }

    #[test]
    fn degenerate_rays_get_keys() {
        let keys = sort_keys(&[ray([f32::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]), ray([f32::INFINITY; 3], [f32::NAN, 1.0, 0.0])]);
        assert!(keys.iter().all(|&k| k < 1 << KEY_BITS));
    }
}
