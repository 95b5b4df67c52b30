//! The compiled SPIR-V of every variant in [`super::variants::VARIANTS`], embedded in the binary.

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// SPIR-V words from bytes (copied: `include_bytes!` gives no 4-byte alignment).
pub fn words(spv: &[u8]) -> anyhow::Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(spv)).map_err(|e| anyhow::anyhow!("reading SPIR-V: {e}"))
}
