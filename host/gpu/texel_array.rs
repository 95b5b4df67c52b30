//! An array the shaders read through a uniform texel buffer (`utextureBuffer` + `texelFetch`)
//! rather than a storage buffer: on lavapipe that turns a per-lane gather of scalar loads into
//! one vector load per lane and texel (docs/experiments/texel-buffer-loads.md).

use super::buffer::{Buffer, TexelFormat, TexelView};
use super::Context;
use anyhow::{bail, Result};
use ash::vk;

/// `bytes` as the unit that keeps a whole number in front: `256 KiB`, `6 MiB` (a limit of
/// 65536 texels of 4 bytes read '0 MiB' before).
fn size_text(bytes: u64) -> String {
    match bytes {
        b if b >= 10 << 20 => format!("{} MiB", b >> 20),
        b if b >= 10 << 10 => format!("{} KiB", b >> 10),
        b => format!("{b} bytes"),
    }
}

/// A device buffer and the texel view the shaders read it through.
pub struct TexelArray<'a> {
    // The view first: fields drop in order, and the view must go before its buffer.
    pub view: TexelView<'a>,
    pub buffer: Buffer<'a>,
}

impl<'a> TexelArray<'a> {
    /// Uploads `data` and views it as `format` texels. An empty array gets one zeroed element,
    /// since a binding needs a buffer even where the shader never reads it. Fails, naming
    /// `name`, if the data hold more texels than the device lets one view address
    /// (`maxTexelBufferElements`; the storage-buffer byte range does not apply).
    pub fn with_data<T: bytemuck::Pod>(ctx: &'a Context, name: &str, data: &[T], format: TexelFormat) -> Result<Self> {
        let bytes = std::mem::size_of_val(data) as u64;
        let limit = ctx.info.max_texel_buffer_elements as u64 * format.bytes();
        if bytes > limit {
            bail!(
                "the scene's {name} take {} texels ({}), over this device's texel-buffer limit of {} texels of {} bytes ({}); \
                 {} can render smaller scenes only",
                bytes / format.bytes(),
                size_text(bytes),
                ctx.info.max_texel_buffer_elements,
                format.bytes(),
                size_text(limit),
                ctx.info.name
            );
        }
        let usage = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let buffer = if data.is_empty() { Buffer::with_data(ctx, name, &[T::zeroed()], usage)? } else { Buffer::with_data(ctx, name, data, usage)? };
        Ok(Self { view: buffer.texel_view(format)?, buffer })
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn sizes_read_in_a_unit_that_keeps_them_whole() {
        assert_eq!(super::size_text(256 << 10), "256 KiB");
        assert_eq!(super::size_text(6 << 20), "6144 KiB");
        assert_eq!(super::size_text(64 << 20), "64 MiB");
        assert_eq!(super::size_text(100), "100 bytes");
    }
}
