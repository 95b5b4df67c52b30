//! The bytes of every glTF buffer: the GLB binary chunk, a `data:` URI (base64, glTF 2.0 spec
//! section 3.6.1.1 "Data URIs") or a file relative to the glTF file (a URI reference, section
//! 2.8: percent-encoded).

use std::path::{Path, PathBuf};

use base64::Engine as _;

use super::at;
use crate::scene::input_file::{read_bounded, MAX_GEOMETRY_BYTES};
use crate::scene::LoadStats;

/// Loads every buffer in `buffers[]` order; each read file is recorded in `stats`.
pub fn load(document: &::gltf::Document, mut blob: Option<Vec<u8>>, file: &Path, dir: &Path, stats: &mut LoadStats) -> anyhow::Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for buffer in document.buffers() {
        let loc = format!("buffers[{}]", buffer.index());
        let mut data = match buffer.source() {
            ::gltf::buffer::Source::Bin => {
                blob.take().ok_or_else(|| at(file, &loc, "refers to the GLB binary chunk, which the file does not have (or a second buffer does too)"))?
            }
            ::gltf::buffer::Source::Uri(uri) => uri_bytes(uri, file, dir, &loc, stats)?,
        };
        if data.len() < buffer.length() {
            let msg = format!("byteLength is {} but only {} bytes are there", buffer.length(), data.len());
            return Err(at(file, &loc, msg));
        }
        // The GLB chunk is padded to 4 bytes; the buffer is its first byteLength bytes.
        data.truncate(buffer.length());
        out.push(data);
    }
    Ok(out)
}

/// The bytes a buffer's or image's `uri` names: a `data:` URI decoded, or the file read (and
/// recorded in `stats`). `loc` is the JSON location, for messages.
pub fn uri_bytes(uri: &str, file: &Path, dir: &Path, loc: &str, stats: &mut LoadStats) -> anyhow::Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((header, payload)) = rest.split_once(',') else {
            return Err(at(file, loc, "malformed data URI (no ',')"));
        };
        if !header.ends_with(";base64") {
            return Err(at(file, loc, format!("data URI '{header}' is not base64 (the only encoding glTF allows)")));
        }
        return base64::engine::general_purpose::STANDARD.decode(payload.trim()).map_err(|e| at(file, loc, format!("data URI is not valid base64: {e}")));
    }
    let path = uri_path(dir, uri);
    let bytes = read_bounded(&path, MAX_GEOMETRY_BYTES).map_err(|e| at(file, loc, format!("{}: {e}", path.display())))?;
    stats.read_input(&path);
    Ok(bytes)
}

/// The file a relative URI reference names: percent-decoded, relative to `dir`.
pub fn uri_path(dir: &Path, uri: &str) -> PathBuf {
    dir.join(percent_decode(uri))
}

/// `%XX` escapes decoded (RFC 3986 section 2.1); anything malformed is kept as written.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%' && i + 2 < b.len() {
            if let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    #[test]
    fn percent_escapes_are_decoded() {
        assert_eq!(super::percent_decode("my%20mesh.bin"), "my mesh.bin");
        assert_eq!(super::percent_decode("a%2"), "a%2");
        assert_eq!(super::percent_decode("plain.bin"), "plain.bin");
    }
}
