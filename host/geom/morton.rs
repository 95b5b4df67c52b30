//! Morton (Z-order) codes in 2D: the bits of two coordinates interleaved, so that nearby codes
//! are nearby cells (ray ordering's direction key, the Z-ordered sampler's cells).

/// Bit i of `x` (below 2^16) moved to bit 2i: one axis of a 2D Morton code.
pub fn spread2(x: u32) -> u32 {
    let mut x = x & 0xffff;
    x = (x | (x << 8)) & 0x00ff_00ff;
    x = (x | (x << 4)) & 0x0f0f_0f0f;
    x = (x | (x << 2)) & 0x3333_3333;
    (x | (x << 1)) & 0x5555_5555
}

/// The inverse of [`spread2`]: bit 2i of `x` moved to bit i (the even-numbered bits, packed).
pub fn compact2(x: u32) -> u32 {
    let mut x = x & 0x5555_5555;
    x = (x | (x >> 1)) & 0x3333_3333;
    x = (x | (x >> 2)) & 0x0f0f_0f0f;
    x = (x | (x >> 4)) & 0x00ff_00ff;
    (x | (x >> 8)) & 0x0000_ffff
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_undoes_spread_and_spread_interleaves() {
        for x in [0u32, 1, 2, 3, 5, 44, 255, 0x1234, 0xffff] {
            assert_eq!(compact2(spread2(x)), x);
            assert_eq!(compact2(spread2(x) >> 1), 0, "spread2({x}) set an odd bit");
        }
        assert_eq!(spread2(5) | (spread2(3) << 1), 0b11011);
    }
}
