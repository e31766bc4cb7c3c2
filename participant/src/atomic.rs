//! Files that appear whole or not at all: a run killed while it writes one
//! leaves the old file or none, never a truncated one.

use std::io;
use std::path::Path;

/// Write aside and rename. On failure (a full disk) the file aside is
/// removed, and the error names the file.
pub fn write_atomic(path: &Path, contents: &str) -> io::Result<()> {
    let tmp = path.with_extension("tmp");
    let written = std::fs::write(&tmp, contents).and_then(|_| std::fs::rename(&tmp, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
    })
}
