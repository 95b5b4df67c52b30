//! Fuzzes the `.npy` readers (`vkrt trace`'s rays, and hit files read back): any file gives its
//! rays or hits or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = std::env::temp_dir().join(format!("vkrt-fuzz-npy-{}.npy", std::process::id()));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    if let Ok(mut rays) = vkrt::output::npy::RayReader::open(&path) {
        while let Ok(batch) = rays.next_batch(1 << 12) {
            if batch.is_empty() {
                break;
            }
        }
    }
    let _ = vkrt::output::npy::read_hits(&path);
});
