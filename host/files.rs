//! Files written whole, and folders of kept files held to a bound.
//!
//! Every file vkrt writes (images, heat maps, rays and hits, checkpoints, cache entries) is made
//! under a temporary name beside its target and renamed over it only when complete: a rename
//! within one folder is atomic, so a reader, a crash or an interrupt sees the old file or the
//! new one, never a part. The caches (prepared scenes, compiled shaders) drop their oldest
//! files past a bound.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// A temporary name beside `path` (same folder, so the rename stays atomic), unique to this
/// process and thread: runs and test threads writing one target never share a temporary file.
pub fn temp_beside(path: &Path) -> PathBuf {
    let mut name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    // ThreadId's Debug form is `ThreadId(N)`; keep the number only.
    let thread: String = format!("{:?}", std::thread::current().id()).chars().filter(char::is_ascii_digit).collect();
    name.push(format!(".{}-{thread}.tmp", std::process::id()));
    path.with_file_name(name)
}

/// Writes `path` whole or not at all: `write` fills the temporary file it is given (see
/// [`temp_beside`]), which is then renamed over `path`. On any error the temporary file is
/// removed and whatever `path` held before is left as it was.
pub fn write_whole<T>(path: &Path, write: impl FnOnce(&Path) -> Result<T>) -> Result<T> {
    let tmp = temp_beside(path);
    let result = write(&tmp).and_then(|value| {
        std::fs::rename(&tmp, path).with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))?;
        Ok(value)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("writing {}", path.display()))
}

/// How much of a folder's kept files [`remove_oldest`] leaves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    Files(usize),
    Bytes(u64),
}

/// Removes the files of `dir` whose names end in `.extension`, oldest modification time first,
/// until they fit in `bound`; never `keep`. Other files are left alone. Best effort, for caches:
/// a file another run removed first, or one that cannot be removed, is passed over.
pub fn remove_oldest(dir: &Path, extension: &str, bound: Bound, keep: Option<&Path>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut files: Vec<(SystemTime, u64, PathBuf)> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == extension))
        .filter_map(|e| e.metadata().ok().map(|m| (m.modified().unwrap_or(SystemTime::UNIX_EPOCH), m.len(), e.path())))
        .collect();
    let mut count = files.len();
    let mut bytes: u64 = files.iter().map(|f| f.1).sum();
    let over = |count: usize, bytes: u64| match bound {
        Bound::Files(n) => count > n,
        Bound::Bytes(b) => bytes > b,
    };
    files.sort();
    for (_, len, path) in files {
        if !over(count, bytes) {
            break;
        }
        if Some(path.as_path()) != keep && std::fs::remove_file(&path).is_ok() {
            count -= 1;
            bytes -= len;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn fresh_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("vkrt-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    #[test]
    fn a_whole_write_replaces_the_file_and_a_failed_one_leaves_it_as_it_was() {
        let dir = fresh_dir("whole");
        let path = dir.join("out.txt");
        write_whole(&path, |tmp| Ok(std::fs::write(tmp, "first")?)).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "first");
        let err = write_whole(&path, |tmp| -> Result<()> {
            std::fs::write(tmp, "half")?;
            anyhow::bail!("interrupted")
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("out.txt") && format!("{err:#}").contains("interrupted"), "{err:#}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "first", "the old file stays whole");
        assert_eq!(names(&dir), ["out.txt"], "no temporary file left");
        assert!(write_whole(&dir.join("missing/out.txt"), |tmp| Ok(std::fs::write(tmp, "x")?)).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn temporary_names_differ_between_threads() {
        let path = Path::new("/somewhere/out.png");
        let here = temp_beside(path);
        let there = std::thread::spawn(move || temp_beside(path)).join().unwrap();
        assert_ne!(here, there);
        assert_eq!(here.parent(), path.parent());
        assert!(here.to_string_lossy().ends_with(".tmp"));
    }

    #[test]
    fn the_oldest_files_go_first_but_never_the_one_kept_nor_other_kinds() {
        let dir = fresh_dir("oldest");
        let now = SystemTime::now();
        let file = |i: u64| {
            let p = dir.join(format!("{i}.bin"));
            std::fs::write(&p, [0u8; 100]).unwrap();
            std::fs::File::options().append(true).open(&p).unwrap().set_modified(now - Duration::from_secs(100 * (4 - i))).unwrap();
            p
        };
        let files: Vec<PathBuf> = (0..4).map(file).collect();
        std::fs::write(dir.join("other.txt"), [0u8; 1000]).unwrap();
        // 400 bytes of .bin, 250 allowed: the two oldest go, unless one is kept.
        remove_oldest(&dir, "bin", Bound::Bytes(250), Some(&files[0]));
        assert_eq!(names(&dir), ["0.bin", "3.bin", "other.txt"]);
        remove_oldest(&dir, "bin", Bound::Files(1), None);
        assert_eq!(names(&dir), ["3.bin", "other.txt"]);
        remove_oldest(&dir, "bin", Bound::Files(1), None);
        assert_eq!(names(&dir), ["3.bin", "other.txt"], "nothing goes while within the bound");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
