//! Fuzzes the PFM reader (`vkrt compare`'s images and references): any bytes give an image or an
//! error, never a panic, and never an allocation the file's own size does not back.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = vkrt::output::image::pfm_from_bytes(data);
});
