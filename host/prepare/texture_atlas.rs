//! All of a scene's textures in two buffers: a table (`GpuTexture[]`) and one array of packed
//! RGBA8 texels, textures one after another. Two bindings hold any number of textures, with no
//! descriptor-array limits to meet (lavapipe, MoltenVK and old drivers differ there). The shaders
//! read both as texel buffers (shaders/include/scene_bindings.glsl), the texels as R32UI.

use crate::gpu_abi::constants::TEXTURE_NONE;
use crate::gpu_abi::GpuTexture;
use crate::scene::Texture;

/// The most texel bytes the atlas may take: 128 MiB, what one storage-buffer binding holds on
/// every Vulkan device, from when the texels were one. As R32UI texels that is 2^25 texels, well
/// inside `maxTexelBufferElements` on lavapipe and desktop GPUs (2^27 or more); `GpuScene::upload`
/// refuses a device whose limit is lower, naming the texels.
pub const TEXEL_BUDGET_BYTES: usize = 1 << 27;

/// The texture table and the texels, ready to upload.
#[derive(Debug, Clone, Default)]
pub struct TextureAtlas {
    pub table: Vec<GpuTexture>,
    pub texels: Vec<u32>,
    /// One warning per texture that had to be halved to fit, for the caller to show.
    pub downsampled: Vec<String>,
}

impl TextureAtlas {
    /// Packs `textures` in order (index i of the table is texture i). If they take more than
    /// `budget` bytes, the largest is halved in each dimension, repeatedly, until they fit:
    /// blurrier textures beat a render that cannot start.
    pub fn pack(textures: &[Texture], budget: usize) -> Self {
        let mut scaled: Vec<std::borrow::Cow<Texture>> = textures.iter().map(std::borrow::Cow::Borrowed).collect();
        let mut halvings = vec![0u32; textures.len()];
        loop {
            let total: usize = scaled.iter().map(|t| t.bytes()).sum();
            if total <= budget {
                break;
            }
            let Some((i, _)) = scaled.iter().enumerate().filter(|(_, t)| t.width * t.height > 1).max_by_key(|(_, t)| t.bytes()) else {
                break;
            };
            scaled[i] = std::borrow::Cow::Owned(scaled[i].downsampled());
            halvings[i] += 1;
        }
        let mut atlas = TextureAtlas::default();
        for (i, t) in scaled.iter().enumerate() {
            if halvings[i] > 0 {
                let orig = &textures[i];
                let line = format!(
                    "texture {} downsampled {}x{} -> {}x{} to fit {} MiB of texels",
                    orig.path.display(),
                    orig.width,
                    orig.height,
                    t.width,
                    t.height,
                    budget >> 20
                );
                atlas.downsampled.push(line);
            }
            atlas.table.push(GpuTexture { offset: atlas.texels.len() as u32, width: t.width, height: t.height, _pad0: 0 });
            atlas.texels.extend_from_slice(&t.texels);
        }
        atlas
    }
}

/// `Option<u32>` texture index as the shaders read it.
pub fn gpu_index(i: Option<u32>) -> u32 {
    i.unwrap_or(TEXTURE_NONE)
}
