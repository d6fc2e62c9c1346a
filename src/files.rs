//! Output files. Every command checks the paths it will write before it starts working
//! ([`check_writable`]), and writes every file through [`write_atomic`]: the bytes go to a
//! temporary file in the target's folder, which is then renamed over the target. A reader, or
//! another smoothlab writing the same name at the same time, sees either the old file or a
//! complete new one, never a mixture; an interrupted run leaves the old file in place.

use std::ffi::OsString;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// The folder a file named `path` goes into (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// True if `path` as written ends with a path separator (`out/`): it names a folder.
pub fn ends_with_separator(path: &Path) -> bool {
    path.as_os_str()
        .to_string_lossy()
        .chars()
        .next_back()
        .is_some_and(std::path::is_separator)
}

/// A fresh file next to `target`, named after it (`.NAME.PID-N.tmp`), created exclusively.
fn create_temporary(target: &Path) -> std::io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = target.file_name().unwrap_or_default();
    loop {
        let mut temp = OsString::from(".");
        temp.push(name);
        temp.push(format!(
            ".{}-{}.tmp",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let path = folder_of(target).join(temp);
        match OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(file) => return Ok((path, file)),
            // Left over by an earlier process with the same id: take the next number.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
}

/// Checks, before any work is done, that a file can be written at `path`: the path does not
/// name a folder (`out/`), it is not an existing folder, device or other non-regular file
/// (which [`write_atomic`] would replace), and its folder exists and accepts new files (tried
/// by creating and removing a temporary file there). The error names the path at fault.
pub fn check_writable(path: &Path) -> Result<()> {
    if ends_with_separator(path) || path.file_name().is_none() {
        return Err(Error::Invalid(format!(
            "{}: names a folder, not a file",
            path.display()
        )));
    }
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(Error::Invalid(format!(
                "{}: is a folder, not a file",
                path.display()
            )));
        }
        if !meta.is_file() {
            return Err(Error::Invalid(format!(
                "{}: is not a regular file (a device, pipe or socket); give a file name",
                path.display()
            )));
        }
    }
    let folder = folder_of(path);
    match std::fs::metadata(folder) {
        Ok(meta) if meta.is_dir() => {}
        Ok(_) => {
            return Err(Error::Invalid(format!(
                "{}: is not a folder",
                folder.display()
            )));
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(Error::Invalid(format!(
                "{}: folder does not exist",
                folder.display()
            )));
        }
        Err(e) => return Err(Error::io(folder, e)),
    }
    let (temp, file) = create_temporary(path).map_err(|e| Error::io(folder, e))?;
    drop(file);
    std::fs::remove_file(&temp).map_err(|e| Error::io(&temp, e))
}

/// Creates `folder` (and its parents) if missing, so that files can be written into it.
pub fn create_folder(folder: &Path) -> Result<()> {
    if folder.as_os_str().is_empty() {
        return Ok(());
    }
    std::fs::create_dir_all(folder).map_err(|e| Error::io(folder, e))
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same folder, then renamed
/// over `path`. On failure the temporary file is removed and `path` is left as it was.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let (temp, mut file) = create_temporary(path).map_err(|e| Error::io(folder_of(path), e))?;
    let written = file
        .write_all(bytes)
        .map_err(|e| Error::io(path, e))
        .and_then(|()| {
            drop(file);
            std::fs::rename(&temp, path).map_err(|e| Error::io(path, e))
        });
    if written.is_err() {
        // Best effort: the error that matters is the one being returned.
        let _ = std::fs::remove_file(&temp);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(test: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("smoothlab-files-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .expect("list")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn atomic_write_replaces_the_file_and_leaves_no_temporary() {
        let dir = scratch("atomic");
        let path = dir.join("a.txt");
        write_atomic(&path, b"first").expect("write");
        write_atomic(&path, b"second").expect("overwrite");
        assert_eq!(std::fs::read(&path).expect("read"), b"second");
        assert_eq!(entries(&dir), ["a.txt"]);
        let err = write_atomic(&dir.join("missing/a.txt"), b"x").expect_err("no folder");
        assert!(err.to_string().contains("missing"), "{err}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn unwritable_targets_are_named_before_any_work() {
        let dir = scratch("check");
        check_writable(&dir.join("new.json")).expect("a new file in an existing folder");
        assert_eq!(entries(&dir), Vec::<String>::new(), "the probe is removed");
        let cases = [
            (dir.join("missing/s.json"), "folder does not exist"),
            (dir.clone(), "is a folder"),
            (
                PathBuf::from(format!("{}/", dir.display())),
                "names a folder",
            ),
            (PathBuf::from("/dev/null"), "not a regular file"),
        ];
        for (path, what) in cases {
            let err = check_writable(&path).expect_err("unwritable");
            let text = err.to_string();
            assert!(text.contains(what), "{}: {text}", path.display());
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
