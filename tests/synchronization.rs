//! The tests run with the validation layers' synchronization validation on (gpu::Context turns
//! it on with the layers): this checks that it really runs, by recording a hazard it must
//! report, and that the barrier vkrt records between dependent commands is one it accepts.

mod common;

use ash::vk;
use vkrt::gpu::commands::{compute_barrier, submit_and_wait};
use vkrt::gpu::{Buffer, MemoryLocation};

/// Fills `a`, then copies it to `b`, with or without vkrt's barrier between the two.
fn fill_then_copy(ctx: &vkrt::gpu::Context, a: &Buffer, b: &Buffer, barrier: bool) {
    submit_and_wait(ctx, "fill then copy", |cmd| unsafe {
        ctx.device.cmd_fill_buffer(cmd, a.buffer, 0, a.size, 7);
        if barrier {
            compute_barrier(ctx, cmd);
        }
        let region = [vk::BufferCopy { src_offset: 0, dst_offset: 0, size: a.size }];
        ctx.device.cmd_copy_buffer(cmd, a.buffer, b.buffer, &region);
    })
    .unwrap();
}

#[test]
fn synchronization_validation_reports_a_missing_barrier_and_accepts_vkrts() {
    let ctx = common::gpu_context();
    if !ctx.validation_enabled {
        eprintln!("SKIPPED synchronization_validation_reports_a_missing_barrier_and_accepts_vkrts: no validation layers (tools/test installs them)");
        return;
    }
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let a = Buffer::new(&ctx, "a", 4096, usage, MemoryLocation::Device).unwrap();
    let b = Buffer::new(&ctx, "b", 4096, usage, MemoryLocation::Device).unwrap();
    fill_then_copy(&ctx, &a, &b, true);
    common::assert_no_validation_messages(&ctx);
    assert_eq!(b.read_as::<u32>(1024).unwrap(), vec![7; 1024]);
    fill_then_copy(&ctx, &a, &b, false);
    let messages = ctx.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("SYNC-HAZARD")),
        "a copy reading a buffer just filled, with no barrier, was not reported: synchronization validation is off ({messages:?})"
    );
}
