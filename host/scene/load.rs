//! Load a scene file by extension (placeholder).
pub fn load_scene(_path: &std::path::Path) -> anyhow::Result<super::Scene> { anyhow::bail!("not yet") }
