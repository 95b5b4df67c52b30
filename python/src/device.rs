//! Vulkan devices for Python: listed as `vkrt info` lists them, and opened once per process.
//!
//! A device is opened on first use and kept until the interpreter exits (creating one takes
//! long next to a small render, and every scene on it borrows it). Vulkan queues need external
//! synchronisation, so work on one device runs one call at a time (`Device::turn`); the GIL is
//! released meanwhile, so other Python threads go on.

use anyhow::Result;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::{Mutex, MutexGuard, OnceLock};
use vkrt::gpu::context::{choose_device, list_devices};
use vkrt::gpu::{Context, ContextOptions};

/// An open device and the lock that serialises its work.
pub struct Device {
    pub ctx: Context,
    work: Mutex<()>,
}

impl Device {
    /// Held while this device's queue works: one call at a time per device.
    pub fn turn(&self) -> MutexGuard<'_, ()> {
        // A thread that panicked while holding it left no device state half-made that the
        // next submission could trip on: every call records and waits on its own work.
        self.work.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// The devices opened so far, by index in `vkrt info`'s list.
fn opened() -> &'static Mutex<Vec<(usize, &'static Device)>> {
    static OPENED: OnceLock<Mutex<Vec<(usize, &'static Device)>>> = OnceLock::new();
    OPENED.get_or_init(|| Mutex::new(Vec::new()))
}

/// `VKRT_DEVICE`, where set and not empty (the command line's `--device` default).
fn device_from_env() -> Option<String> {
    std::env::var("VKRT_DEVICE").ok().filter(|s| !s.is_empty())
}

/// The device `wanted` names (an index or part of a name, as `--device`), else `VKRT_DEVICE`,
/// else the default (a discrete GPU, else the best other device: lavapipe without a GPU).
pub fn open(wanted: Option<&str>) -> Result<&'static Device> {
    let wanted = wanted.map(str::to_string).or_else(device_from_env);
    let infos = list_devices()?;
    let index = choose_device(&infos, wanted.as_deref())?;
    let mut opened = opened().lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, d)) = opened.iter().find(|(i, _)| *i == index) {
        return Ok(d);
    }
    let options = ContextOptions { device: Some(index.to_string()), shader_cache: vkrt::cli::user_shader_cache(), ..ContextOptions::from_env() };
    let device: &'static Device = Box::leak(Box::new(Device { ctx: Context::new(&options)?, work: Mutex::new(()) }));
    opened.push((index, device));
    Ok(device)
}

/// `vkrt.devices()`: every Vulkan device, as `vkrt info` lists them.
#[pyfunction]
pub fn devices(py: Python<'_>) -> PyResult<Vec<Py<PyDict>>> {
    use crate::errors::IntoPy;
    let infos = list_devices().py_err()?;
    let chosen = choose_device(&infos, device_from_env().as_deref()).ok();
    infos
        .iter()
        .map(|d| {
            let dict = PyDict::new(py);
            dict.set_item("index", d.index)?;
            dict.set_item("name", &d.name)?;
            dict.set_item("type", d.type_name())?;
            dict.set_item("driver", format!("{} {}", d.driver_name, d.driver_info))?;
            dict.set_item("usable", d.usable)?;
            dict.set_item("default", Some(d.index) == chosen)?;
            dict.set_item("subgroup_size", d.subgroup_size)?;
            dict.set_item("max_storage_buffer_range", d.max_storage_buffer_range)?;
            dict.set_item("max_texel_buffer_elements", d.max_texel_buffer_elements)?;
            dict.set_item("max_workgroup_invocations", d.max_workgroup_invocations)?;
            dict.set_item("device_local_bytes", d.device_local_bytes)?;
            Ok(dict.unbind())
        })
        .collect()
}
