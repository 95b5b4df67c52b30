//! Fuzzes the OBJ + MTL loader: the input is an OBJ, optionally followed by a 0xFF byte and the
//! MTL file it may name as `mtllib f.mtl`. The loader must return a scene or an error, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = match data.iter().position(|&b| b == 0xFF) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    let dir = std::env::temp_dir().join(format!("vkrt-fuzz-obj-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("f.obj");
    if std::fs::write(&path, obj).is_ok() && std::fs::write(dir.join("f.mtl"), mtl).is_ok() {
        let _ = vkrt::scene::load_scene(&path);
    }
});
