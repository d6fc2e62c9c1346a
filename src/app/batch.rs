//! `smoothlab report` over a user's data set and parameter sweeps: the flags `--meshes`,
//! `--scheme`, `--sweep` and `--sweep-file` turned into a [`WorkList`].
//!
//! - `--meshes DIR` takes every mesh file of the folder (`.obj`, `.ply`, `.off`, `.stl`, case
//!   ignored, not descending into subfolders; an entry so named that is no readable file, such
//!   as a folder or a broken link, is recorded as an error) in byte order of the names; `--meshes LIST` (any
//!   other file) takes the paths listed one per line, relative to the list's folder (blank lines
//!   and lines starting with `#` skipped; a leading byte-order mark and CR LF line ends are
//!   accepted); a mesh file given as the list is an error. A mesh is named in the report by its file name (folder)
//!   or by its line (list).
//! - `--scheme all|S1,S2,…` chooses the schemes (default `all`).
//! - `--sweep SCHEME:NAME=V1,V2,…[:NAME2=…]` measures the scheme at every combination of the
//!   values (the first parameter varying slowest); repeatable, and `--sweep-file F` reads one
//!   such line per line. A sweep replaces `--scheme`: only the swept variants are measured.
//!
//! Faces are counted before loading, cheaply (OBJ `f` records, the PLY/OFF header counts, the
//! binary STL facet count, ASCII STL `facet` lines), to balance shards by cost; a file that
//! cannot be counted weighs its size in bytes / 64 and fails later, as an error record.

use std::path::{Path, PathBuf};

use crate::error::{Error, Problem, Result};
use crate::mesh::{LoadOptions, MeshFormat};
use crate::report::batch::{MeshSource, Variant, WorkItem, WorkList};
use crate::schemes::{self, Params, SCHEMES};

/// The variants of `--scheme` (`all`, one name or a comma-separated list) when no sweep is given,
/// else those of the sweeps (`--sweep` values, then the lines of the `--sweep-file`s).
pub(crate) fn variants(
    selection: &str,
    sweeps: &[String],
    sweep_files: &[PathBuf],
) -> Result<Vec<Variant>> {
    let mut lines: Vec<(String, String)> = sweeps
        .iter()
        .map(|s| ("--sweep".to_string(), s.clone()))
        .collect();
    for file in sweep_files {
        let text = std::fs::read_to_string(file).map_err(|e| Error::io(file, e))?;
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if !line.is_empty() && !line.starts_with('#') {
                lines.push((format!("{}:{}", file.display(), n + 1), line.to_string()));
            }
        }
    }
    if lines.is_empty() {
        return scheme_list(selection);
    }
    let mut out: Vec<Variant> = Vec::new();
    for (origin, line) in lines {
        for v in parse_sweep(&line).map_err(|e| e.within(origin.as_str()))? {
            if !out.contains(&v) {
                out.push(v);
            }
        }
    }
    Ok(out)
}

/// `variants` with `report --param` pairs `raw` (`name=value`) as the defaults of every
/// variant whose scheme declares the name; a name no variant's scheme declares is an error
/// naming it and the parameters they have.
pub(crate) fn with_defaults(mut variants: Vec<Variant>, raw: &[String]) -> Result<Vec<Variant>> {
    let pairs = crate::app::selection::parse_params(raw)?;
    for (name, _) in &pairs {
        let declared = |v: &Variant| {
            schemes::find(&v.scheme).is_ok_and(|s| s.params.iter().any(|p| p.name == name))
        };
        if !variants.iter().any(declared) {
            let mut known: Vec<&str> = variants
                .iter()
                .filter_map(|v| schemes::find(&v.scheme).ok())
                .flat_map(|s| s.params.iter().map(|p| p.name))
                .collect();
            known.sort_unstable();
            known.dedup();
            return Err(Error::config(
                "--param",
                Problem::Other {
                    text: format!(
                        "{name}: no scheme of the report has a parameter '{name}' (they have: {})",
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                },
            ));
        }
    }
    for v in &mut variants {
        let Ok(spec) = schemes::find(&v.scheme) else {
            continue;
        };
        v.defaults = pairs
            .iter()
            .filter(|(n, _)| spec.params.iter().any(|p| p.name == n))
            .cloned()
            .collect();
    }
    Ok(variants)
}

/// The schemes of `--scheme`: `all` (every registered scheme) or names separated by commas.
fn scheme_list(selection: &str) -> Result<Vec<Variant>> {
    if selection.trim() == crate::app::selection::ALL_SCHEMES {
        return Ok(SCHEMES
            .iter()
            .map(|s| Variant::default_of(s.name))
            .collect());
    }
    let mut out: Vec<Variant> = Vec::new();
    for name in selection.split(',').map(str::trim) {
        let v = Variant::default_of(schemes::find(name)?.name);
        if !out.contains(&v) {
            out.push(v);
        }
    }
    Ok(out)
}

/// Parses one sweep, `SCHEME:NAME=V1,V2,…[:NAME2=W1,…]`, into its variants: every combination
/// of the values, the first parameter varying slowest. The scheme and parameter names are
/// checked against the registry; the values when the scheme is built.
pub(crate) fn parse_sweep(text: &str) -> Result<Vec<Variant>> {
    let mut parts = text.split(':');
    let scheme = schemes::find(parts.next().unwrap_or_default().trim())?;
    let sweep_error = |reason: String| {
        Error::config(
            "sweep",
            Problem::Other {
                text: format!("'{text}': {reason}"),
            },
        )
    };
    let mut axes: Vec<(String, Vec<String>)> = Vec::new();
    for part in parts {
        let (name, values) = part.split_once('=').ok_or_else(|| {
            sweep_error(format!(
                "'{part}' is not NAME=V1,V2,… (e.g. hb:beta=0.1,0.2)"
            ))
        })?;
        let name = name.trim().to_string();
        let values: Vec<String> = values.split(',').map(|v| v.trim().to_string()).collect();
        if name.is_empty() || values.iter().any(String::is_empty) {
            return Err(sweep_error(format!("'{part}' has an empty name or value")));
        }
        if axes.iter().any(|(n, _)| *n == name) {
            return Err(sweep_error(format!("parameter '{name}' is given twice")));
        }
        axes.push((name, values));
    }
    if axes.is_empty() {
        return Err(Error::config(
            "sweep",
            Problem::Other {
                text: format!(
                    "'{text}' sweeps no parameter (e.g. {}:NAME=V1,V2)",
                    scheme.name
                ),
            },
        ));
    }
    let names: Vec<(String, String)> = axes
        .iter()
        .map(|(n, v)| (n.clone(), v[0].clone()))
        .collect();
    Params::resolve(scheme, &names)?;
    let mut combos: Vec<Vec<(String, String)>> = vec![Vec::new()];
    for (name, values) in &axes {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((name.clone(), v.clone()));
                    c
                })
            })
            .collect();
    }
    Ok(combos
        .into_iter()
        .map(|params| Variant {
            defaults: Vec::new(),
            scheme: scheme.name.to_string(),
            params,
        })
        .collect())
}

/// The mesh files of `--meshes`: a folder's mesh files, or the files a list names. Returns
/// (name in the report, path) in order; two meshes of one name are an error naming both.
pub(crate) fn mesh_files(source: &Path) -> Result<Vec<(String, PathBuf)>> {
    let mut out: Vec<(String, PathBuf)> = Vec::new();
    if source.is_dir() {
        let entries = std::fs::read_dir(source).map_err(|e| Error::io(source, e))?;
        for entry in entries {
            // Every entry named as a mesh file is an item, also one that cannot be read (a
            // folder `x.obj`, a broken symbolic link, a link loop): it becomes an error record
            // instead of vanishing from the report.
            let path = entry.map_err(|e| Error::io(source, e))?.path();
            if MeshFormat::from_path(&path).is_ok() {
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                out.push((name, path));
            }
        }
        out.sort();
        if out.is_empty() {
            return Err(Error::Invalid(format!(
                "{}: no mesh files ({}) in the folder",
                source.display(),
                MeshFormat::supported_extensions()
            )));
        }
    } else if let Ok(format) = MeshFormat::from_path(source) {
        return Err(Error::Invalid(format!(
            "{}: this is a mesh ({} file); --meshes takes a folder of meshes or a list of mesh \
             files, one per line",
            source.display(),
            format.name()
        )));
    } else {
        let text = std::fs::read_to_string(source).map_err(|e| Error::io(source, e))?;
        // A list saved by a Windows editor may start with a byte-order mark.
        let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
        let base = source.parent().unwrap_or(Path::new(""));
        // `lines` ends lines at LF and CR LF alike.
        for line in text.lines().map(str::trim) {
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            if let Some((first, _)) = out.iter().find(|(name, _)| name == line) {
                return Err(Error::Invalid(format!(
                    "{}: '{line}' is listed twice ({first})",
                    source.display()
                )));
            }
            out.push((line.to_string(), base.join(line)));
        }
        if out.is_empty() {
            return Err(Error::Invalid(format!(
                "{}: the list names no mesh file",
                source.display()
            )));
        }
    }
    Ok(out)
}

/// The work list of `report --meshes SOURCE` with `variants` on every mesh.
pub(crate) fn mesh_work(
    source: &Path,
    variants: &[Variant],
    load: &LoadOptions,
) -> Result<WorkList> {
    let items = mesh_files(source)?
        .into_iter()
        .map(|(mesh, path)| WorkItem {
            faces: count_faces(&path),
            mesh,
            source: MeshSource::File(path),
            variants: variants.to_vec(),
        })
        .collect();
    Ok(WorkList::new(items, load))
}

/// The number of triangles of a mesh file, estimated without loading it (see the module doc)
/// and at most its size in bytes; 0 when the file cannot be read.
pub(crate) fn count_faces(path: &Path) -> usize {
    // Only regular files are read: a pipe named x.obj would never end.
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return 0;
    }
    let Ok(bytes) = std::fs::read(path) else {
        return 0;
    };
    let by_size = bytes.len() / 64;
    let counted = match MeshFormat::from_path(path) {
        Ok(MeshFormat::Obj) => Some(obj_faces(&bytes)),
        Ok(MeshFormat::Ply) => header_count(&bytes, |l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            (w.len() == 3 && w[0] == "element" && w[1] == "face").then(|| w[2].parse().ok())?
        }),
        Ok(MeshFormat::Off) => off_faces(&bytes),
        Ok(MeshFormat::Stl) => stl_faces(&bytes),
        Err(_) => None,
    };
    // A header's count is the file's claim; every triangle takes at least a byte.
    counted.map_or(by_size, |n| n.min(bytes.len()))
}

/// OBJ: a polygon of n corners is n − 2 triangles.
fn obj_faces(bytes: &[u8]) -> usize {
    bytes
        .split(|b| *b == b'\n')
        .filter(|l| l.starts_with(b"f ") || l.starts_with(b"f\t"))
        .map(|l| {
            let corners = l[1..]
                .split(|b| b.is_ascii_whitespace())
                .filter(|w| !w.is_empty())
                .count();
            corners.saturating_sub(2)
        })
        .sum()
}

/// The first count a header line gives, searching the first 64 lines.
fn header_count(bytes: &[u8], count: impl Fn(&str) -> Option<usize>) -> Option<usize> {
    let head = &bytes[..bytes.len().min(4096)];
    String::from_utf8_lossy(head)
        .lines()
        .take(64)
        .find_map(count)
}

/// OFF: the face count is the second number of the first non-comment line after the keyword.
fn off_faces(bytes: &[u8]) -> Option<usize> {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
    let mut words = head
        .lines()
        .map(|l| l.split('#').next().unwrap_or_default())
        .flat_map(str::split_whitespace)
        .skip_while(|w| !w.ends_with("OFF"))
        .skip(1);
    words.next()?;
    words.next()?.parse().ok()
}

/// STL: binary when the size matches the facet count in the header, else `facet` lines.
fn stl_faces(bytes: &[u8]) -> Option<usize> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * n {
            return Some(n);
        }
    }
    Some(
        String::from_utf8_lossy(bytes)
            .lines()
            .filter(|l| l.trim_start().starts_with("facet"))
            .count(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    #[test]
    fn sweeps_expand_to_every_combination() {
        let v = parse_sweep("hb:beta=0.1,0.2:gamma0=-1,0").expect("sweep");
        let labels: Vec<String> = v.iter().map(Variant::label).collect();
        assert_eq!(
            labels,
            [
                "hb:beta=0.1:gamma0=-1",
                "hb:beta=0.1:gamma0=0",
                "hb:beta=0.2:gamma0=-1",
                "hb:beta=0.2:gamma0=0"
            ]
        );
        for (bad, says) in [
            ("nope:beta=1", "nope"),
            ("hb:bogus=1", "bogus"),
            ("hb", "sweeps no parameter"),
            ("hb:beta", "'beta' is not NAME=V1"),
            ("hb:beta=1,", "empty name or value"),
            ("hb:beta=1:beta=2", "given twice"),
        ] {
            let err = parse_sweep(bad).expect_err(bad);
            assert!(err.to_string().contains(says), "{bad}: {err}");
        }
    }

    /// Sweep syntax and `--param` errors are typed configuration errors, worded as before;
    /// a sweep's origin is their place.
    #[test]
    fn sweep_and_param_errors_are_config_errors() {
        let is_sweep = |err: &Error| matches!(err, Error::Config { key, problem: Problem::Other { .. } } if key == "sweep");
        for (bad, says) in [
            ("hb", "sweep 'hb' sweeps no parameter (e.g. hb:NAME=V1,V2)"),
            (
                "hb:beta",
                "sweep 'hb:beta': 'beta' is not NAME=V1,V2,… (e.g. hb:beta=0.1,0.2)",
            ),
            (
                "hb:beta=1,",
                "sweep 'hb:beta=1,': 'beta=1,' has an empty name or value",
            ),
            (
                "hb:beta=1:beta=2",
                "sweep 'hb:beta=1:beta=2': parameter 'beta' is given twice",
            ),
        ] {
            let err = parse_sweep(bad).expect_err(bad);
            assert!(is_sweep(&err), "{bad}: {err:?}");
            assert_eq!(err.to_string(), says);
        }
        let err = variants("all", &["hb".into()], &[]).expect_err("no parameter");
        assert!(
            matches!(err, Error::In { ref place, ref error } if place == "--sweep" && is_sweep(error)),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            "--sweep: sweep 'hb' sweeps no parameter (e.g. hb:NAME=V1,V2)"
        );
        let err = with_defaults(vec![Variant::default_of("flat")], &["beta=1".into()])
            .expect_err("flat has no beta");
        assert_config_error(
            &err,
            "--param",
            |p| matches!(p, Problem::Other { .. }),
            "--param beta: no scheme of the report has a parameter 'beta' (they have: none)",
        );
    }

    #[test]
    fn scheme_lists_and_sweep_files() {
        let v = variants("flat, pn,flat", &[], &[]).expect("list");
        assert_eq!(v, [Variant::default_of("flat"), Variant::default_of("pn")]);
        assert_eq!(variants("all", &[], &[]).expect("all").len(), SCHEMES.len());
        assert!(variants("flat,nope", &[], &[]).is_err());
        let dir = std::env::temp_dir().join(format!("smoothlab-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let file = dir.join("sweep.txt");
        std::fs::write(
            &file,
            "# loop94 and hb\nloop94:beta=0.5,0.8\n\nhb:beta=x:y\n",
        )
        .expect("write");
        let err = variants("all", &[], std::slice::from_ref(&file)).expect_err("bad line 4");
        assert!(err.to_string().contains("sweep.txt:4: "), "{err}");
        std::fs::write(&file, "loop94:beta=0.5,0.8\n").expect("write");
        let v = variants("all", &["pn:normals=estimate".into()], &[file]).expect("sweeps");
        let labels: Vec<String> = v.iter().map(Variant::label).collect();
        assert_eq!(
            labels,
            ["pn:normals=estimate", "loop94:beta=0.5", "loop94:beta=0.8"]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn lists_may_start_with_a_byte_order_mark_and_end_lines_in_crlf() {
        let dir = std::env::temp_dir().join(format!("smoothlab-list-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let list = dir.join("meshes.txt");
        std::fs::write(&list, "\u{feff}a/one.obj\r\n# skipped\r\n\r\nb.off\r\n").expect("write");
        let files = mesh_files(&list).expect("list");
        assert_eq!(
            files,
            [
                ("a/one.obj".to_string(), dir.join("a/one.obj")),
                ("b.off".to_string(), dir.join("b.off"))
            ]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_mesh_given_as_the_list_is_an_error() {
        let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj");
        let err = mesh_files(&mesh).expect_err("a mesh is no list");
        assert_eq!(
            err.to_string(),
            format!(
                "{}: this is a mesh (OBJ file); --meshes takes a folder of meshes or a list of \
                 mesh files, one per line",
                mesh.display()
            )
        );
    }

    #[test]
    fn faces_are_counted_without_loading() {
        assert_eq!(obj_faces(b"v 0 0 0\nf 1 2 3\nf 1 2 3 4\n# f\nf\t1 2 3"), 4);
        assert_eq!(off_faces(b"OFF\n# c\n4 2 0\n"), Some(2));
        assert_eq!(off_faces(b"COFF 8 12 0\n"), Some(12));
        let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nelement face 7\nend_header\n";
        assert_eq!(
            header_count(ply, |l| l.strip_prefix("element face ")?.parse().ok()),
            Some(7)
        );
        let mut stl = vec![0u8; 84 + 100];
        stl[80] = 2;
        assert_eq!(stl_faces(&stl), Some(2));
        assert_eq!(
            stl_faces(b"solid a\n facet normal 0 0 1\n facet normal 0 0 1\n"),
            Some(2)
        );
        // A count the file cannot hold weighs the file's size.
        let dir = std::env::temp_dir().join(format!("smoothlab-count-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let off = dir.join("huge.off");
        let text = "OFF\n3 18446744073709551615 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        std::fs::write(&off, text).expect("write");
        assert_eq!(count_faces(&off), text.len());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
