//! `vkrt info`: the Vulkan devices and the limits that matter to vkrt.

use super::DeviceArgs;
use anyhow::Result;

pub fn run(args: &DeviceArgs) -> Result<()> {
    let devices = crate::gpu::context::list_devices()?;
    let chosen = crate::gpu::context::choose_device(&devices, args.device.as_deref()).ok();
    for d in &devices {
        let mark = if Some(d.index) == chosen { "  <- vkrt uses this one" } else { "" };
        println!("{d}{mark}");
    }
    if devices.is_empty() {
        println!("no Vulkan devices found");
    }
    Ok(())
}
