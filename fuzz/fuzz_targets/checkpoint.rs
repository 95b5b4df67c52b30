//! Fuzzes the checkpoint reader (`render --resume`, `vkrt merge`): any bytes give a checkpoint
//! or an error, never a panic, and never an allocation the file's own size does not back.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = vkrt::integrator::path::checkpoint::Checkpoint::from_bytes(data);
});
