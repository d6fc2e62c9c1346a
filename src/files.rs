//! Output files. Every command checks the paths it will write before it starts working
//! ([`check_writable`]), and writes every file through [`write_atomic`]: the bytes go to a
//! temporary file in the target's folder, which is then renamed over the target. A reader, or
//! another smoothlab writing the same name at the same time, sees either the old file or a
//! complete new one, never a mixture; an interrupted run leaves the old file in place.
//!
//! Temporary files are registered while they exist; with [`clean_up_on_signals`] an interrupt (SIGINT, SIGTERM, SIGHUP) removes them before the
//! process ends, so that no half-written `.NAME.PID-N.tmp` stays behind.
//!
//! Names: every path written must be valid UTF-8 ([`utf8_path`]), so that the names derived
//! from it (frames, cells, shard parts) and the names recorded in JSON are the same bytes.
//! [`check_distinct`] refuses an output that would overwrite an input of the same run, or two
//! outputs of one run on one file.

use std::ffi::OsString;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
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
pub(crate) fn ends_with_separator(path: &Path) -> bool {
    path.as_os_str()
        .to_string_lossy()
        .chars()
        .next_back()
        .is_some_and(std::path::is_separator)
}

/// The temporary files that exist now (created, not yet renamed or removed).
static LIVE_TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The list of live temporaries, also after a thread panicked while holding it.
fn live_temporaries() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE_TEMPORARIES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Forgets the temporary `path` (it was renamed or removed).
fn forget_temporary(path: &Path) {
    live_temporaries().retain(|p| p != path);
}

/// The exit code of a run ended by an interrupt (128 + SIGINT, as shells report it).
pub(crate) const INTERRUPTED_EXIT_CODE: i32 = 130;

/// The exit code and the standard-error line of an interrupt.
static INTERRUPT_OUTCOME: Mutex<(i32, &str)> = Mutex::new((
    INTERRUPTED_EXIT_CODE,
    "error: interrupted; temporary files removed\n",
));

/// Makes an interrupt the normal end of this process (a server that runs until Ctrl-C): the
/// handler of [`clean_up_on_signals`] still removes the temporaries, then prints `message`
/// (one line) and exits with code 0.
pub(crate) fn interrupt_is_the_normal_end(message: &'static str) {
    *INTERRUPT_OUTCOME
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner) = (0, message);
}

/// Installs the handler of SIGINT, SIGTERM and SIGHUP: it removes the temporary files that
/// exist at that moment and ends the process with [`INTERRUPTED_EXIT_CODE`]. Files already
/// renamed into place are complete; those being written keep their old contents. The list of
/// temporaries stays locked until the process has ended, so that no other thread can create
/// one after the clean-up.
pub fn clean_up_on_signals() -> Result<()> {
    ctrlc::set_handler(|| {
        let mut live = live_temporaries();
        for path in live.drain(..) {
            // Best effort: a temporary renamed a moment ago is no longer there.
            let _ = std::fs::remove_file(path);
        }
        let (code, message) = *INTERRUPT_OUTCOME
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let _ = std::io::stderr().lock().write_all(message.as_bytes());
        std::process::exit(code);
    })
    .map_err(|e| Error::Invalid(format!("cannot install the interrupt handler: {e}")))
}

/// The longest file name most file systems accept, in bytes.
const NAME_MAX: usize = 255;

/// The most bytes of the target's name a temporary's name repeats: room is left for the dot in
/// front and `.PID-N.tmp` behind within [`NAME_MAX`], so that a target name the file system
/// accepts always has a temporary it accepts too.
const TEMPORARY_NAME_KEEP: usize = NAME_MAX - 48;

/// The start of the temporary's name for a target named `name`: `.` and at most
/// [`TEMPORARY_NAME_KEEP`] bytes of the name, cut at a character boundary.
fn temporary_prefix(name: &std::ffi::OsStr) -> OsString {
    let mut prefix = OsString::from(".");
    match name.to_str() {
        Some(text) if text.len() > TEMPORARY_NAME_KEEP => {
            let mut end = TEMPORARY_NAME_KEEP;
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            prefix.push(&text[..end]);
        }
        Some(text) => prefix.push(text),
        None => prefix.push("smoothlab"),
    }
    prefix
}

/// A fresh file next to `target`, named after it (`.NAME.PID-N.tmp`, NAME shortened when
/// long, see [`temporary_prefix`]), created exclusively and registered as live until
/// [`forget_temporary`].
fn create_temporary(target: &Path) -> std::io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let prefix = temporary_prefix(target.file_name().unwrap_or_default());
    loop {
        let mut temp = prefix.clone();
        temp.push(format!(
            ".{}-{}.tmp",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let path = folder_of(target).join(temp);
        // Registered before it exists, so that an interrupt between the two still removes it.
        live_temporaries().push(path.clone());
        let created = OpenOptions::new().write(true).create_new(true).open(&path);
        if created.is_err() {
            forget_temporary(&path);
        }
        match created {
            Ok(file) => return Ok((path, file)),
            // Left over by an earlier process with the same id: take the next number.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
}

/// Checks, before any work is done, that a file can be written at `path`: the path does not
/// name a folder (`out/`), it is not an existing folder, device or other non-regular file
/// (which [`write_atomic`] would replace), its folder exists — a missing folder is created,
/// with its parents, for every output of every command alike — and accepts new files (tried
/// by creating and removing a temporary file there), the path is UTF-8 ([`utf8_path`]) and
/// its file name at most 255 bytes long.
/// The error names the path at fault.
pub(crate) fn check_writable(path: &Path) -> Result<()> {
    utf8_path(path)?;
    if let Some(name) = path.file_name()
        && name.len() > NAME_MAX
    {
        return Err(Error::Invalid(format!(
            "{}: the file name is {} bytes long, more than the {NAME_MAX} bytes file systems \
             accept; give a shorter name",
            path.display(),
            name.len()
        )));
    }
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
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => create_folder(folder)?,
        Err(e) => return Err(Error::io(folder, e)),
    }
    let (temp, file) = create_temporary(path).map_err(|e| Error::io(folder, e))?;
    drop(file);
    let removed = std::fs::remove_file(&temp).map_err(|e| Error::io(&temp, e));
    forget_temporary(&temp);
    removed
}

/// Creates `folder` (and its parents) if missing, so that files can be written into it.
pub(crate) fn create_folder(folder: &Path) -> Result<()> {
    if folder.as_os_str().is_empty() {
        return Ok(());
    }
    std::fs::create_dir_all(folder).map_err(|e| Error::io(folder, e))
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same folder, then renamed
/// over `path`. On failure the temporary file is removed and `path` is left as it was.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
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
    forget_temporary(&temp);
    written
}

/// `path` as UTF-8 text, or an error naming it: smoothlab writes only files whose paths are
/// valid UTF-8, so that every name derived from an output name (frames, cells, shard parts)
/// and every name recorded in a JSON file is the same bytes as the one given.
pub(crate) fn utf8_path(path: &Path) -> Result<&str> {
    path.to_str().ok_or_else(|| {
        Error::Invalid(format!(
            "{}: the path is not valid UTF-8 (shown with U+FFFD where its bytes are not); \
             smoothlab writes files under UTF-8 names only: give another name",
            path.display()
        ))
    })
}

/// The file `path` names, for comparing paths: the canonical path when it exists, else its
/// folder's canonical path joined with its file name (or the path as given when the folder
/// does not exist either).
fn identity(path: &Path) -> PathBuf {
    if let Ok(canonical) = std::fs::canonicalize(path) {
        return canonical;
    }
    match (std::fs::canonicalize(folder_of(path)), path.file_name()) {
        (Ok(folder), Some(name)) => folder.join(name),
        _ => path.to_path_buf(),
    }
}

/// True if `a` and `b` are one file: the same canonical path, or (on Unix) two hard links of
/// one existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    if identity(a) == identity(b) {
        return true;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(a), Ok(b)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return a.dev() == b.dev() && a.ino() == b.ino();
        }
    }
    false
}

/// Checks, before any work is done, that no output of a run overwrites one of its inputs or
/// another of its outputs. `inputs` and `outputs` are `(role, path)` pairs, the role naming
/// the flag or the file's part in the run (`--json`, `the mesh`, `the PNG image`) for the
/// error, which names the path and both roles.
pub(crate) fn check_distinct(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<()> {
    for (k, (role, output)) in outputs.iter().enumerate() {
        if let Some((input_role, _)) = inputs.iter().find(|(_, input)| same_file(input, output)) {
            return Err(Error::Invalid(format!(
                "{}: {role} would overwrite {input_role}, an input of this run; give the output \
                 another name",
                output.display()
            )));
        }
        if let Some((other_role, _)) = outputs[..k]
            .iter()
            .find(|(_, other)| same_file(other, output))
        {
            return Err(Error::Invalid(format!(
                "{}: written both as {other_role} and as {role}; give them different names",
                output.display()
            )));
        }
    }
    Ok(())
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
        check_writable(&dir.join("new/folders/s.json")).expect("missing folders are created");
        assert!(dir.join("new/folders").is_dir());
        std::fs::write(dir.join("file"), b"").expect("a file");
        let cases = [
            (dir.join("file/s.json"), "file: is not a folder"),
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

    #[test]
    fn long_target_names_get_temporaries_the_file_system_accepts() {
        let dir = scratch("long");
        for len in [245, 250, NAME_MAX] {
            let path = dir.join(format!("{}.json", "g".repeat(len - 5)));
            check_writable(&path).expect("probe");
            write_atomic(&path, b"{}").expect("write under a long name");
            assert_eq!(std::fs::read(&path).expect("read"), b"{}");
        }
        let too_long = dir.join("g".repeat(NAME_MAX + 1));
        let err = check_writable(&too_long).expect_err("longer than file systems accept");
        assert!(
            err.to_string()
                .contains("is 256 bytes long, more than the 255"),
            "{err}"
        );
        // A name cut inside a multi-byte character keeps whole characters.
        let prefix = temporary_prefix(std::ffi::OsStr::new(&"é".repeat(200)));
        assert!(prefix.len() <= TEMPORARY_NAME_KEEP + 1, "{}", prefix.len());
        assert!(prefix.to_str().is_some_and(|p| p.ends_with('é')));
        assert_eq!(
            entries(&dir).len(),
            3,
            "no temporary left: {:?}",
            entries(&dir)
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn temporaries_are_registered_while_they_exist() {
        let dir = scratch("live");
        let ours = || -> Vec<PathBuf> {
            live_temporaries()
                .iter()
                .filter(|p| p.starts_with(&dir))
                .cloned()
                .collect()
        };
        let (temp, file) = create_temporary(&dir.join("a.exr")).expect("temporary");
        assert_eq!(ours(), std::slice::from_ref(&temp));
        drop(file);
        std::fs::remove_file(&temp).expect("remove");
        forget_temporary(&temp);
        write_atomic(&dir.join("a.exr"), b"exr").expect("write");
        check_writable(&dir.join("b.exr")).expect("probe");
        assert_eq!(ours(), Vec::<PathBuf>::new());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[cfg(unix)]
    #[test]
    fn paths_that_are_not_utf8_are_refused_by_name() {
        use std::os::unix::ffi::OsStrExt;
        let dir = scratch("utf8");
        let path = dir.join(std::ffi::OsStr::from_bytes(b"L17\xffname.png"));
        let err = check_writable(&path).expect_err("not UTF-8");
        let text = err.to_string();
        assert!(
            text.contains("L17\u{fffd}name.png") && text.contains("not valid UTF-8"),
            "{text}"
        );
        assert_eq!(entries(&dir), Vec::<String>::new());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn an_output_on_an_input_or_on_another_output_is_named() {
        let dir = scratch("distinct");
        let mesh = dir.join("m.obj");
        std::fs::write(&mesh, "v 0 0 0\n").expect("mesh");
        let json = dir.join("m.json");
        check_distinct(&[("the mesh", &mesh)], &[("--json", &json)]).expect("distinct");
        // The same file written another way: through `..`, and as a hard link.
        let roundabout = dir.join("sub/../m.obj");
        std::fs::create_dir_all(dir.join("sub")).expect("sub");
        let err = check_distinct(&[("the mesh", &mesh)], &[("--json", &roundabout)])
            .expect_err("the output is the input");
        let text = err.to_string();
        assert!(text.contains("--json would overwrite the mesh"), "{text}");
        let link = dir.join("link.obj");
        std::fs::hard_link(&mesh, &link).expect("hard link");
        assert!(check_distinct(&[("the mesh", &mesh)], &[("-o", &link)]).is_err());
        let png = dir.join("out.png");
        let err = check_distinct(
            &[],
            &[("the PNG image", &png), ("--stats", &dir.join("./out.png"))],
        )
        .expect_err("two outputs on one file");
        let text = err.to_string();
        assert!(
            text.contains("out.png: written both as the PNG image and as --stats"),
            "{text}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
