//! Reading a scene's files: regular files only, and no more than a stated size.
//!
//! A scene names other files (an OBJ's `mtllib`, a glTF buffer's `uri`, a lab YAML's meshes),
//! so a path from a file can be anything: an `mtllib /dev/zero` was read without end until the
//! kernel killed vkrt (24 GB resident in under a minute), and opening a FIFO blocks until some
//! writer appears. So the file's type is checked before it is opened, and it is read through a
//! bound, which also holds if the file grows while it is read.

use std::io::Read;
use std::path::Path;

/// The most bytes a geometry file (OBJ, glTF, GLB, a glTF buffer) may hold: far above the
/// 10M-triangle scenes vkrt is measured on, below what a 24 GiB machine can take in.
pub const MAX_GEOMETRY_BYTES: u64 = 16 << 30;

/// The most bytes a description file (an MTL library, a lab YAML scene) may hold.
pub const MAX_DESCRIPTION_BYTES: u64 = 256 << 20;

/// The whole file at `path`, if it is a regular file (or a link to one) of at most `limit`
/// bytes; otherwise a message saying why not, for the caller to put beside the file's name.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let meta = regular_file(path)?;
    if meta.len() > limit {
        return Err(too_large(meta.len(), limit));
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read the file: {e}"))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| format!("cannot read the file: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// The metadata of `path` if it is a regular file (or a link to one), without opening it;
/// otherwise a message saying what it is.
pub fn regular_file(path: &Path) -> Result<std::fs::Metadata, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read the file: {e}"))?;
    if !meta.is_file() {
        return Err(format!("cannot read it: {} is not a regular file", kind_of(&meta)));
    }
    Ok(meta)
}

fn too_large(bytes: u64, limit: u64) -> String {
    format!("the file holds {bytes} bytes, more than the {} MiB vkrt reads from a file of this kind", limit >> 20)
}

/// What a path that is not a regular file is, for the message.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "something that"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_regular_file_up_to_its_bound_and_no_further() {
        let dir = std::env::temp_dir().join(format!("vkrt-input-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("ten.txt");
        std::fs::write(&path, b"0123456789").unwrap();
        assert_eq!(read_bounded(&path, 10).unwrap(), b"0123456789");
        let err = read_bounded(&path, 9).unwrap_err();
        assert!(err.contains("10 bytes"), "{err}");
        let err = read_bounded(&dir, 100).unwrap_err();
        assert!(err.contains("a directory is not a regular file"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn refuses_a_device_without_reading_it() {
        let err = read_bounded(Path::new("/dev/zero"), MAX_DESCRIPTION_BYTES).unwrap_err();
        assert!(err.contains("a character device is not a regular file"), "{err}");
    }
}
