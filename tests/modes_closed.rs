//! A render mode is one closed unit: its file in `src/render/modes/` and its line in the
//! registry (`modes! { … }` of `src/render/modes/mod.rs`). No code outside `render/modes/`
//! names a particular mode — no `Mode::<Variant>`, no mode's parameter type — so that a new
//! mode needs nothing anywhere else; the command line, scene files, figure specs, the viewer
//! and the turntables take it from the registry.

use std::path::{Path, PathBuf};

use smoothlab::render::modes::{MODE_FLAGS, MODE_HELP, MODE_KEYS, MODE_NAMES};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read src") {
        let path = entry.expect("dir entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The registry's lines: `(variant, parameter type)` of every mode, read from the
/// `modes! { … }` invocation.
fn registry() -> Vec<(String, String)> {
    let text = std::fs::read_to_string(src().join("render/modes/mod.rs")).expect("modes/mod.rs");
    let start = text.find("\nmodes! {").expect("the registry invocation");
    let body = &text[start..];
    let end = body.find("\n}").expect("end of the registry");
    body[..end]
        .lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("//") && l.ends_with("),"))
        .filter_map(|l| {
            let (variant, ty) = l.trim_end_matches("),").split_once('(')?;
            let ty = ty.rsplit("::").next()?.to_string();
            Some((variant.trim().to_string(), ty))
        })
        .collect()
}

/// Whether `word` occurs in `line` as a whole identifier (not inside a longer one).
fn names(line: &str, word: &str) -> bool {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    line.match_indices(word).any(|(at, _)| {
        let before = line[..at].chars().next_back();
        let after = line[at + word.len()..].chars().next();
        !before.is_some_and(ident) && !after.is_some_and(ident)
    })
}

#[test]
fn the_registry_lists_every_mode_once() {
    let modes = registry();
    assert_eq!(modes.len(), MODE_NAMES.len(), "{modes:?} vs {MODE_NAMES:?}");
    assert_eq!(MODE_HELP.len(), MODE_NAMES.len());
    assert_eq!(MODE_KEYS.len(), MODE_NAMES.len());
    assert_eq!(MODE_FLAGS.len(), MODE_NAMES.len());
    let mut names = MODE_NAMES.to_vec();
    names.sort_unstable();
    names.dedup();
    assert_eq!(
        names.len(),
        MODE_NAMES.len(),
        "a mode name twice: {MODE_NAMES:?}"
    );
    // A flag declared by several modes (a shared switch) sets the same key in each.
    for (mode, flags) in MODE_FLAGS {
        for flag in flags.iter() {
            assert!(
                MODE_KEYS
                    .iter()
                    .find(|(m, _)| m == mode)
                    .is_some_and(|(_, keys)| keys.iter().any(|k| k.name == flag.key)),
                "--{} of {mode} sets {}, not a key of [{mode}]",
                flag.long,
                flag.key
            );
        }
    }
}

#[test]
fn no_code_outside_render_modes_names_a_mode() {
    let modes = registry();
    assert!(modes.len() >= 8, "registry not found: {modes:?}");
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let inside = src().join("render").join("modes");
    let mut found = Vec::new();
    for file in files.iter().filter(|f| !f.starts_with(&inside)) {
        let text = std::fs::read_to_string(file).expect("source");
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for (variant, ty) in &modes {
                let variant_path = format!("Mode::{variant}");
                // A mode's parameter type may be defined outside (the path tracer's
                // `ShadedParams` in render/shaded.rs); only its own file names it.
                // A type named like its variant (`Normals`) is common as a word elsewhere
                // (`Overlay::NAMES` holds `patches`): only its path through the modes counts.
                let defines = text.contains(&format!("pub struct {ty}"));
                let type_named = if ty == variant {
                    names(code, &format!("modes::{ty}"))
                } else {
                    names(code, ty)
                };
                if names(code, &variant_path) || (!defines && type_named) {
                    found.push(format!(
                        "{}:{}: {}",
                        file.strip_prefix(src()).unwrap_or(file).display(),
                        n + 1,
                        line.trim()
                    ));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "modes named outside src/render/modes/:\n{}",
        found.join("\n")
    );
}

/// The user guide's table of render modes names every registered mode, and its page on
/// rendering every mode flag (the registry is what the binary takes; the guide must not fall
/// behind).
#[test]
fn the_guide_names_every_mode_and_flag() {
    let guide = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide/rendering.md"),
    )
    .expect("docs/guide/rendering.md");
    let table = guide
        .split("\n## Modes\n")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .expect("the guide's 'Modes' section");
    for name in MODE_NAMES {
        assert!(
            table.contains(&format!("| `{name}` |")),
            "the guide's table of modes misses `{name}`"
        );
    }
    for (mode, flags) in MODE_FLAGS {
        for flag in flags.iter() {
            assert!(
                guide.contains(&format!("--{}", flag.long)),
                "docs/guide/rendering.md misses --{} of {mode}",
                flag.long
            );
        }
    }
}
