//! The user guide in `docs/` is checked against the program: every figure `metrics` prints or
//! writes is explained in `docs/metrics.md`, every paper the code cites is in
//! `docs/bibliography.md`, the CLI reference `docs/cli.md` is the program's `--help`, every key
//! the scene-file and figure-spec parsers accept is in their key references, every relative
//! link of the README and the guide resolves, and the README's quickstart runs.
//!
//! `SMOOTHLAB_UPDATE_DOCS=1 cargo test --release --test docs` rewrites `docs/cli.md` instead of
//! failing when it is stale.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use common::{path_str, scratch, smoothlab, stderr};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn doc(name: &str) -> String {
    let path = root().join("docs").join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every column of the text table and every key of the JSON (of every scheme) is named, in
/// backquotes, in the metrics glossary.
#[test]
fn every_metrics_column_and_key_is_explained() {
    let glossary = doc("metrics.md");
    let dir = scratch("docs", "metrics");
    let json = dir.join("m.json");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj");
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "all",
        "--json",
        path_str(&json),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let table = String::from_utf8(out.stdout).expect("utf-8");
    let header = table.lines().next().expect("a header line");
    let mut missing: Vec<String> = header
        .split_whitespace()
        .filter(|column| !glossary.contains(&format!("`{column}`")))
        .map(|column| format!("column {column}"))
        .collect();
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    let schemes = value.as_array().expect("one object per scheme");
    assert!(schemes.len() >= 8, "{}", schemes.len());
    for scheme in schemes {
        for key in scheme.as_object().expect("an object").keys() {
            let entry = format!("key {key}");
            if !glossary.contains(&format!("`{key}`")) && !missing.contains(&entry) {
                missing.push(entry);
            }
        }
    }
    assert!(missing.is_empty(), "not in docs/metrics.md: {missing:?}");
}

/// Every short name the code cites a paper by (`[HB00 eq. 17]`, `[Piper87 §3.8]`, …) has a row
/// in the bibliography.
#[test]
fn every_cited_paper_is_in_the_bibliography() {
    let bibliography = doc("bibliography.md");
    let listed: Vec<&str> = bibliography
        .lines()
        .filter_map(|line| line.strip_prefix("| "))
        .filter_map(|row| row.split(" |").next())
        .collect();
    let mut cited = std::collections::BTreeSet::new();
    let mut stack = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("src")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("src folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let text = std::fs::read_to_string(&path).expect("source file");
            // Citations are in comments: `[HB00 eq. 17]`, `[Piper87 §3.8 step 5]`, `[FM, t = 2]`.
            let comments = text
                .lines()
                .filter(|line| line.trim_start().starts_with("//"));
            for line in comments {
                // Code in backquotes (`[[Re Ĝ, −Im Ĝ], …]`) is not prose.
                let line: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
                for (start, _) in line.match_indices('[') {
                    let name: String = line[start + 1..]
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric())
                        .collect();
                    let after = line[start + 1 + name.len()..].chars().next();
                    let starts_upper = name.chars().next().is_some_and(|c| c.is_ascii_uppercase());
                    if name.len() >= 2 && starts_upper && matches!(after, Some(' ' | ',')) {
                        cited.insert(name);
                    }
                }
            }
        }
    }
    for name in ["HB00", "Piper87", "UP", "FM"] {
        assert!(cited.contains(name), "{name} not found among the citations");
    }
    let missing: Vec<&String> = cited
        .iter()
        .filter(|name| !listed.contains(&name.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "cited but not in docs/bibliography.md: {missing:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// The CLI reference

/// The subcommands `smoothlab --help` lists (without `help`).
fn subcommands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|line| !line.starts_with("Commands:"))
        .skip(1)
        .take_while(|line| !line.trim().is_empty())
        .filter_map(|line| line.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_owned)
        .collect()
}

fn help_text(args: &[&str]) -> String {
    let out = smoothlab(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    String::from_utf8(out.stdout).expect("utf-8")
}

/// `docs/cli.md` as the program's help renders it: `smoothlab --help`, then `smoothlab CMD
/// --help` of every subcommand in the order `--help` lists them.
fn cli_reference() -> String {
    let top = help_text(&["--help"]);
    let mut text = String::from(
        "# CLI reference\n\n\
         Every command of `smoothlab` with its flags and defaults, as `smoothlab CMD --help` prints\n\
         them. This page is generated from the program: `tests/docs.rs` fails when it is stale, and\n\
         `SMOOTHLAB_UPDATE_DOCS=1 cargo test --release --test docs cli_reference` rewrites it.\n\
         What the commands do is in the [user guide](README.md).\n",
    );
    let commands = subcommands(&top);
    text.push_str("\n## `smoothlab`\n\n```text\n");
    text.push_str(top.trim_end());
    text.push_str("\n```\n");
    for command in &commands {
        let help = help_text(&[command.as_str(), "--help"]);
        text.push_str(&format!("\n## `smoothlab {command}`\n\n```text\n"));
        text.push_str(help.trim_end());
        text.push_str("\n```\n");
    }
    text
}

#[test]
fn cli_reference_is_the_programs_help() {
    let generated = cli_reference();
    for command in [
        "render", "figure", "metrics", "export", "report", "view", "merge",
    ] {
        assert!(
            generated.contains(&format!("## `smoothlab {command}`")),
            "{command} missing from the generated reference"
        );
    }
    let path = root().join("docs/cli.md");
    if std::env::var_os("SMOOTHLAB_UPDATE_DOCS").is_some() {
        std::fs::write(&path, &generated).expect("write docs/cli.md");
        return;
    }
    let written = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        written == generated,
        "docs/cli.md is stale: run `SMOOTHLAB_UPDATE_DOCS=1 cargo test --release --test docs \
         cli_reference` and commit it"
    );
}

// ---------------------------------------------------------------------------------------------
// The key references of scene files and figure specs

const PROBE: &str = "zz_not_a_key";

/// The fields a parser error lists after "expected one of" (or "expected `x`"), if the error is
/// about the unknown probe key.
fn expected_fields(err: &str) -> Option<Vec<String>> {
    let at = err.find(&format!("unknown field `{PROBE}`"))?;
    let rest = &err[at..];
    let list = &rest[rest.find("expected")?..];
    let end = list.find('\n').unwrap_or(list.len());
    Some(
        list[..end]
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_owned)
            .collect(),
    )
}

/// Every key `command` (`render` or `figure`) accepts in its TOML file, as `key` or
/// `section.key`, found by giving it an unknown key at the top level and in every key read as a
/// table (`[key]`) or an array of tables (`[[key]]`): the parser's error lists what it accepts.
fn accepted_keys(command: &str, dir: &Path) -> BTreeSet<String> {
    let probe = |text: &str| -> Option<Vec<String>> {
        let file = dir.join(format!("{command}-probe.toml"));
        std::fs::write(&file, text).expect("probe file");
        let out = smoothlab(&[command, path_str(&file)]);
        assert!(!out.status.success(), "{text} was accepted");
        expected_fields(&stderr(&out))
    };
    let top = probe(&format!("{PROBE} = 1\n"))
        .unwrap_or_else(|| panic!("{command}: no list of accepted keys"));
    assert!(top.len() >= 4, "{command}: {top:?}");
    let mut keys = BTreeSet::new();
    for key in top {
        let section = probe(&format!("[{key}]\n{PROBE} = 1\n"))
            .or_else(|| probe(&format!("[[{key}]]\n{PROBE} = 1\n")));
        match section {
            Some(fields) => keys.extend(fields.into_iter().map(|f| format!("{key}.{f}"))),
            None => {
                keys.insert(key);
            }
        }
    }
    keys
}

/// The key names of the table rows of the "Key reference" part of `text`: the backquoted
/// names of each row's first cell.
fn documented_keys(text: &str) -> BTreeSet<String> {
    let reference = &text[text.find("## Key reference").expect("a key reference")..];
    reference
        .lines()
        .filter_map(|line| line.strip_prefix("| "))
        .filter_map(|row| row.split(" |").next())
        .flat_map(|cell| {
            cell.split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_owned)
                .collect::<Vec<_>>()
        })
        .filter(|name| name != "key")
        .collect()
}

fn check_key_reference(command: &str, doc_name: &str, test: &str) {
    let dir = scratch("docs", test);
    let accepted = accepted_keys(command, &dir);
    let documented = documented_keys(&doc(doc_name));
    let missing: Vec<&String> = accepted.difference(&documented).collect();
    let stale: Vec<&String> = documented.difference(&accepted).collect();
    assert!(
        missing.is_empty() && stale.is_empty(),
        "docs/{doc_name}: keys the parser accepts but the reference lacks: {missing:?}; keys \
         the reference lists but the parser refuses: {stale:?}"
    );
}

#[test]
fn every_scene_key_is_in_the_scene_reference() {
    check_key_reference("render", "guide/scenes.md", "scene_keys");
}

#[test]
fn every_figure_spec_key_is_in_the_figure_reference() {
    check_key_reference("figure", "guide/figures.md", "figure_keys");
}

// ---------------------------------------------------------------------------------------------
// The README and the links

/// README.md, ARCHITECTURE.md and every Markdown file under docs/.
fn markdown_files() -> Vec<PathBuf> {
    let mut files = vec![root().join("README.md"), root().join("ARCHITECTURE.md")];
    let mut stack = vec![root().join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("docs folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The anchors of the headings of Markdown `text` as a forge names them: lower case, letters,
/// digits, `-` and `_` kept, spaces made `-`, everything else dropped. Code blocks are skipped.
fn anchors(text: &str) -> BTreeSet<String> {
    let mut in_code = false;
    let mut anchors = BTreeSet::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code || !line.starts_with('#') {
            continue;
        }
        let title = line.trim_start_matches('#').trim();
        let slug: String = title
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        anchors.insert(slug);
    }
    anchors
}

/// The targets of the inline links and images `[text](target)` of `text`, outside code.
fn link_targets(text: &str) -> Vec<String> {
    let mut in_code = false;
    let mut targets = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        for (at, _) in line.match_indices("](") {
            let rest = &line[at + 2..];
            if let Some(end) = rest.find(')') {
                targets.push(rest[..end].to_owned());
            }
        }
    }
    targets
}

#[test]
fn every_relative_link_resolves() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in markdown_files() {
        let text = std::fs::read_to_string(&file).expect("markdown");
        let folder = file.parent().expect("folder");
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let (path, anchor) = match target.split_once('#') {
                Some((path, anchor)) => (path, Some(anchor)),
                None => (target.as_str(), None),
            };
            let resolved = if path.is_empty() {
                file.clone()
            } else {
                folder.join(path)
            };
            let name = file.strip_prefix(root()).unwrap_or(&file).display();
            if !resolved.exists() {
                broken.push(format!("{name}: {target}"));
                continue;
            }
            if let Some(anchor) = anchor {
                let target_text = std::fs::read_to_string(&resolved).unwrap_or_default();
                if !anchors(&target_text).contains(anchor) {
                    broken.push(format!("{name}: {target} (no such heading)"));
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} links found");
    assert!(broken.is_empty(), "broken links: {broken:#?}");
}

#[test]
fn the_readme_is_short_and_opens_with_a_picture() {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README");
    let lines = readme.lines().count();
    assert!(
        lines <= 200,
        "README.md has {lines} lines; the guide is docs/"
    );
    let first_image = readme
        .lines()
        .position(|line| line.starts_with("!["))
        .expect("an image");
    assert!(
        first_image < 8,
        "the first image is on line {}",
        first_image + 1
    );
    // The first two commands are the default job and the tests (CI runs them as documented).
    let commands: Vec<&str> = readme
        .lines()
        .filter(|line| line.starts_with("cargo "))
        .collect();
    assert_eq!(
        &commands[1..3],
        ["cargo run --release", "cargo test --release"],
        "{commands:?}"
    );
}

/// The commands of the README's quickstart run as written, in a folder holding `my.obj` (the
/// scanned bunny) and the `compare.toml` the README shows.
#[test]
fn the_readme_quickstart_runs() {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README");
    let start = readme.find("## Quickstart").expect("a quickstart");
    let end = readme[start + 3..]
        .find("\n## ")
        .map_or(readme.len(), |e| start + 3 + e);
    let section = &readme[start..end];
    let block = |fence: &str| -> String {
        let at = section
            .find(fence)
            .unwrap_or_else(|| panic!("no {fence} block"))
            + fence.len();
        let len = section[at..].find("```").expect("closed block");
        section[at..at + len].to_owned()
    };
    let commands: Vec<Vec<String>> = block("```sh\n")
        .lines()
        .filter_map(|line| line.strip_prefix("smoothlab "))
        .map(|line| {
            let line = line.split('#').next().unwrap_or(line);
            line.split_whitespace().map(str::to_owned).collect()
        })
        .collect();
    assert_eq!(commands.len(), 3, "{commands:?}");
    let dir = scratch("docs", "quickstart");
    std::fs::copy(root().join("scenes/bunny.obj"), dir.join("my.obj")).expect("mesh");
    std::fs::write(dir.join("compare.toml"), block("```toml\n")).expect("spec");
    for args in &commands {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args(args)
            .current_dir(&dir)
            .output()
            .expect("run smoothlab");
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    }
    for written in [
        "my-hb-zebra.png",
        "my-hb-zebra.exr",
        "compare.png",
        "compare.svg",
    ] {
        assert!(dir.join(written).is_file(), "{written} not written");
    }
}
