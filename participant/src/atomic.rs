//! Files that appear whole or not at all: a run killed while it writes one
//! leaves the old file or none, never a truncated one.

use std::io;
use std::path::{Path, PathBuf};

/// The extension of a file being written aside.
const ASIDE: &str = "tmp";

/// Where the file at `path` is written before it is renamed to `path`:
/// beside it, its name and `.tmp`.
pub fn aside(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".");
    name.push(ASIDE);
    path.with_file_name(name)
}

/// Write aside and rename. On failure (a full disk) the file aside is
/// removed, and the error names the file.
pub fn write_atomic(path: &Path, contents: &str) -> io::Result<()> {
    let tmp = aside(path);
    let written = std::fs::write(&tmp, contents).and_then(|_| std::fs::rename(&tmp, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
    })
}

/// Remove the files left aside in `dir` and the folders under it by a
/// process killed while it wrote them: never a complete file, which is
/// only ever renamed into place. Call it once nothing writes there any
/// more. Returns how many were removed.
pub fn remove_left_aside(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let path = entry.path();
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            removed += remove_left_aside(&path);
        } else if path.extension().is_some_and(|x| x == ASIDE) {
            removed += std::fs::remove_file(&path).is_ok() as usize;
        }
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Files aside (as `write_atomic` and run checkpoints leave them when
    /// killed) go, at any depth; whole files, even with a dot in their
    /// name, stay.
    #[test]
    fn only_files_left_aside_are_removed() {
        let dir = std::env::temp_dir().join(format!("canopy-aside-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let deep = dir.join("checkpoints").join("000000000499");
        std::fs::create_dir_all(&deep).unwrap();
        let whole = [dir.join("bodies.pvd"), deep.join("fluid.state")];
        for w in &whole {
            write_atomic(w, "whole").unwrap();
        }
        for w in &whole {
            std::fs::write(aside(w), "").unwrap();
        }
        assert_eq!(aside(&whole[0]), dir.join("bodies.pvd.tmp"));
        assert_eq!(remove_left_aside(&dir), 2);
        for w in &whole {
            assert_eq!(std::fs::read_to_string(w).unwrap(), "whole");
            assert!(!aside(w).exists());
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
