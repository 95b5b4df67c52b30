//! An array the shaders read through a uniform texel buffer (`utextureBuffer` + `texelFetch`)
//! rather than a storage buffer: on lavapipe that turns a per-lane gather of scalar loads into
//! one vector load per lane and texel (docs/experiments/texel-buffer-loads.md).

use super::buffer::{Buffer, TexelFormat, TexelView};
use super::Context;
use anyhow::{bail, Result};
use ash::vk;

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
                "the scene's {name} take {} MiB, over this device's {} MiB texel-buffer limit ({} texels of {} bytes)",
                bytes >> 20,
                limit >> 20,
                ctx.info.max_texel_buffer_elements,
                format.bytes()
            );
        }
        let usage = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let buffer = if data.is_empty() { Buffer::with_data(ctx, name, &[T::zeroed()], usage)? } else { Buffer::with_data(ctx, name, data, usage)? };
        Ok(Self { view: buffer.texel_view(format)?, buffer })
    }
}
