//! The compiled SPIR-V of every variant in [`super::variants::VARIANTS`], embedded in the binary.

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// SPIR-V words from bytes (copied: `include_bytes!` gives no 4-byte alignment).
pub fn words(spv: &[u8]) -> anyhow::Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(spv)).map_err(|e| anyhow::anyhow!("reading SPIR-V: {e}"))
}

/// The SPIR-V of shader `base` compiled for `layout` (variant `base` + the layout's suffix).
/// Errors if the table has no such variant, rather than walking the nodes with the wrong shader.
pub fn for_layout(base: &str, layout: crate::layout::LayoutKind) -> anyhow::Result<&'static [u8]> {
    let name = format!("{base}{}", layout.variant_suffix());
    ALL.iter()
        .find(|(n, _)| *n == name)
        .map(|(_, spv)| *spv)
        .ok_or_else(|| anyhow::anyhow!("shader '{base}' has no variant for the {} layout ('{name}')", layout.name()))
}
