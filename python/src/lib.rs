//! `vkrt._vkrt`, the compiled half of the `vkrt` Python package (python/vkrt/__init__.py is
//! the other: argument checks, numpy conversions, docstrings). A second front end beside the
//! command line, built on the same library and the command line's own resolution rules, so the
//! two give the same bytes.

mod device;
mod errors;
mod render;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _vkrt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::Scene>()?;
    m.add_class::<render::Progressive>()?;
    m.add_function(wrap_pyfunction!(device::devices, m)?)?;
    m.add_function(wrap_pyfunction!(scene::_load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::_scene_from_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(render::_render, m)?)?;
    m.add_function(wrap_pyfunction!(render::_resume, m)?)?;
    m.add_function(wrap_pyfunction!(render::_merge, m)?)?;
    m.add_function(wrap_pyfunction!(render::_write_image, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
