//! Compiled compute shaders kept between runs: the binary of a shader object
//! (`vkGetShaderBinaryDataEXT`, gpu::shader_objects) in a folder, one file per shader, device
//! and specialization. A file is only ever a whole binary (written to a temporary file, then
//! renamed), and a binary the driver refuses (another driver, or a damaged file) is made again
//! from the SPIR-V and written over.

use crate::files::{self, Bound};
use std::path::{Path, PathBuf};

/// The kept binaries' file extension.
const EXTENSION: &str = "bin";

/// Files kept at most; past it, the oldest written go (a path shader build with its
/// specialization is ~100-300 kB on lavapipe, so this bounds the folder near 100 MB).
pub const MAX_ENTRIES: usize = 512;

/// Everything that makes one compiled shader: the device's binary identity
/// (`shaderBinaryUUID`, `shaderBinaryVersion`) and its own words for itself, the SPIR-V, the
/// specialization constants and the interface (bindings and their kinds, push-constant bytes).
pub struct ShaderKey<'a> {
    pub binary_uuid: [u8; 16],
    pub binary_version: u32,
    /// Device name, driver and subgroup size: lavapipe's binary identity is its Mesa version
    /// alone, while its code is for the vector width its name gives ("256 bits") and
    /// `LP_NATIVE_VECTOR_WIDTH` changes (tools/test runs the GPU tests at two widths).
    pub device: &'a str,
    pub spirv: &'a [u8],
    pub constants: &'a [(u32, u32)],
    pub bindings: &'a [(u32, u32)],
    pub push_size: u32,
}

impl ShaderKey<'_> {
    /// The file this shader is kept in under `dir`: the xxh3-128 of the key, in hex.
    pub fn file_in(&self, dir: &Path) -> PathBuf {
        let mut bytes = Vec::with_capacity(self.spirv.len() + 64);
        bytes.extend_from_slice(&self.binary_uuid);
        bytes.extend_from_slice(&self.binary_version.to_le_bytes());
        bytes.extend_from_slice(&(self.device.len() as u64).to_le_bytes());
        bytes.extend_from_slice(self.device.as_bytes());
        bytes.extend_from_slice(&(self.spirv.len() as u64).to_le_bytes());
        bytes.extend_from_slice(self.spirv);
        for list in [self.constants, self.bindings] {
            bytes.extend_from_slice(&(list.len() as u64).to_le_bytes());
            for &(a, b) in list {
                bytes.extend_from_slice(&a.to_le_bytes());
                bytes.extend_from_slice(&b.to_le_bytes());
            }
        }
        bytes.extend_from_slice(&self.push_size.to_le_bytes());
        dir.join(format!("{:032x}.{EXTENSION}", xxhash_rust::xxh3::xxh3_128(&bytes)))
    }
}

/// The binary kept in `file`, if there is one, in memory aligned to 16 bytes as
/// `vkCreateShadersEXT` requires of a binary.
pub fn load(file: &Path) -> Option<Aligned> {
    let bytes = std::fs::read(file).ok().filter(|b| !b.is_empty())?;
    let mut words = vec![0u128; bytes.len().div_ceil(16)];
    bytemuck::cast_slice_mut::<u128, u8>(&mut words)[..bytes.len()].copy_from_slice(&bytes);
    Some(Aligned { words, len: bytes.len() })
}

/// Bytes at a 16-byte aligned address.
pub struct Aligned {
    words: Vec<u128>,
    len: usize,
}

impl std::ops::Deref for Aligned {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        &bytemuck::cast_slice(&self.words)[..self.len]
    }
}

/// Keeps `binary` in `file` (creating its folder), whole or not at all; then trims the folder
/// to [`MAX_ENTRIES`]. A cache that cannot be written is no error: the run goes on without it,
/// and the reason comes back for a warning.
pub fn store(file: &Path, binary: &[u8]) -> Result<(), String> {
    let dir = file.parent().ok_or_else(|| format!("{}: no folder", file.display()))?;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    files::write_whole(file, |tmp| Ok(std::fs::write(tmp, binary)?)).map_err(|e| format!("{e:#}"))?;
    files::remove_oldest(dir, EXTENSION, Bound::Files(MAX_ENTRIES), Some(file));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key<'a>(spirv: &'a [u8], constants: &'a [(u32, u32)]) -> ShaderKey<'a> {
        ShaderKey { binary_uuid: [7; 16], binary_version: 1, device: "llvmpipe (256 bits) 8", spirv, constants, bindings: &[(0, 1)], push_size: 16 }
    }

    #[test]
    fn every_part_of_the_key_names_another_file() {
        let dir = Path::new("/cache");
        let base = key(b"spirv", &[(1, 2)]).file_in(dir);
        assert_eq!(base, key(b"spirv", &[(1, 2)]).file_in(dir));
        assert_ne!(base, key(b"spirV", &[(1, 2)]).file_in(dir));
        assert_ne!(base, key(b"spirv", &[(1, 3)]).file_in(dir));
        assert_ne!(base, key(b"spirv", &[(1, 2), (3, 4)]).file_in(dir));
        assert_ne!(base, ShaderKey { binary_version: 2, ..key(b"spirv", &[(1, 2)]) }.file_in(dir));
        assert_ne!(base, ShaderKey { binary_uuid: [8; 16], ..key(b"spirv", &[(1, 2)]) }.file_in(dir));
        assert_ne!(base, ShaderKey { device: "llvmpipe (128 bits) 4", ..key(b"spirv", &[(1, 2)]) }.file_in(dir));
        assert_ne!(base, ShaderKey { push_size: 32, ..key(b"spirv", &[(1, 2)]) }.file_in(dir));
        assert_ne!(base, ShaderKey { bindings: &[(0, 2)], ..key(b"spirv", &[(1, 2)]) }.file_in(dir));
    }

    #[test]
    fn store_writes_whole_files_and_keeps_at_most_max_entries() {
        let dir = std::env::temp_dir().join(format!("vkrt-shader-cache-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let file = dir.join("a.bin");
        store(&file, b"binary").unwrap();
        let loaded = load(&file).unwrap();
        assert_eq!(&loaded[..], b"binary");
        assert_eq!(loaded.as_ptr() as usize % 16, 0);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        for i in 0..MAX_ENTRIES + 2 {
            store(&dir.join(format!("{i}.bin")), b"x").unwrap();
        }
        let left = std::fs::read_dir(&dir).unwrap().count();
        assert_eq!(left, MAX_ENTRIES);
        assert!(dir.join(format!("{}.bin", MAX_ENTRIES + 1)).exists(), "the file just stored stays");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
