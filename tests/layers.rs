//! The layering of ARCHITECTURE.md, checked against the code: every top-level module of
//! `src/` imports only the modules its layer allows, and no two files import each other,
//! directly or through others.
//!
//! What counts as an import: every `crate::…`, `super::…` and `self::…` path in non-test code
//! (everything but the items and fields gated by `#[cfg(test)]`, found by bracket matching;
//! files named `tests.rs` or `test_support.rs` are test code), comments left out. Test code
//! may use any module, as may `testing`, the test support shared by the unit tests, `tests/`
//! and `benches/`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layer graph: each top-level module and the modules directly below it. A module may
/// import those and, transitively, everything below them (the crate root's re-exports of
/// `error` — `crate::Result`, `crate::Error` — count as `error`); nothing else, and never a
/// module above it or beside it (e.g. `render` and `metrics` do not import `schemes`).
const BELOW: &[(&str, &[&str])] = &[
    ("error", &[]),
    ("tolerance", &[]),
    ("geom", &["error", "tolerance"]),
    ("linalg", &["error", "tolerance"]),
    ("files", &["error", "tolerance"]),
    ("budget", &["error", "tolerance"]),
    ("text", &[]),
    ("progress", &[]),
    ("bezier", &["geom", "linalg"]),
    ("mesh", &["geom", "linalg", "files", "budget"]),
    ("blend", &["bezier"]),
    ("surface", &["blend"]),
    ("schemes", &["surface", "mesh", "progress"]),
    ("metrics", &["surface", "mesh"]),
    ("export", &["surface", "mesh", "files", "budget"]),
    (
        "render",
        &["surface", "mesh", "files", "budget", "text", "progress"],
    ),
    (
        "report",
        &["schemes", "metrics", "export", "render", "progress"],
    ),
    ("app", &["report"]),
];

/// The modules `module` may import: the transitive closure of [`BELOW`].
fn allowed(module: &str) -> Option<BTreeSet<&'static str>> {
    let direct: BTreeMap<&str, &[&str]> = BELOW.iter().copied().collect();
    let mut reach = BTreeSet::new();
    let mut todo: Vec<&str> = direct.get(module)?.to_vec();
    while let Some(m) = todo.pop() {
        if reach.insert(m) {
            todo.extend(direct.get(m).copied().unwrap_or(&[]));
        }
    }
    Some(reach)
}

/// The test-support module, which may import anything and which only test code imports.
const TESTING: &str = "testing";

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

/// The module path of a file (`src/render/modes/mod.rs` → `["render", "modes"]`).
fn module_of(file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src()).expect("under src");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The file that defines module `path`, if it is a file of its own.
fn file_of(path: &[String]) -> Option<PathBuf> {
    if path.is_empty() {
        return None;
    }
    let base = path.iter().fold(src(), |p, part| p.join(part));
    [base.with_extension("rs"), base.join("mod.rs")]
        .into_iter()
        .find(|p| p.is_file())
}

/// The non-test code of `file`, comments removed.
fn code_of(file: &Path) -> Option<String> {
    let name = file.file_name()?.to_string_lossy();
    if name == "tests.rs" || name == "test_support.rs" {
        return None;
    }
    let text = std::fs::read_to_string(file).expect("read source");
    Some(without_test_items(&without_comments(&text)))
}

/// `text` without its `//` comments (to the end of the line; a `//` in a string literal
/// ends the line's code as well, which only drops text).
fn without_comments(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `code` without the items and fields gated by `#[cfg(test)]`: from the attribute to the
/// end of the item it gates — its `;` or `,` at nesting depth 0 (a `use`, `mod NAME;`, a
/// struct field or a field of a struct literal), or the `}` closing its first brace (a `mod`
/// block, a function, an `impl`). Everything else is kept, so every other line is checked.
fn without_test_items(code: &str) -> String {
    const GATE: &str = "#[cfg(test)]";
    let mut out = String::with_capacity(code.len());
    let mut rest = code;
    while let Some(at) = rest.find(GATE) {
        out.push_str(&rest[..at]);
        let item = &rest[at + GATE.len()..];
        rest = &item[gated_item_len(item)..];
    }
    out.push_str(rest);
    out
}

/// The length of the item at the start of `code` (after its `#[cfg(test)]`), by bracket
/// matching with string and character literals skipped; all of `code` if it never ends.
fn gated_item_len(code: &str) -> usize {
    let bytes = code.as_bytes();
    // Depth of (), [] and, before the first brace, the generics' <>; then depth of {}.
    let mut depth = 0i32;
    let mut braces = 0i32;
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'\'' if bytes.get(i + 2) == Some(&b'\'') => i += 2,
            b'\'' if bytes.get(i + 1) == Some(&b'\\') => {
                i += 2;
                while i < bytes.len() && bytes[i] != b'\'' {
                    i += 1;
                }
            }
            b'{' => braces += 1,
            b'}' => {
                braces -= 1;
                if braces <= 0 {
                    return i + 1;
                }
            }
            _ if braces > 0 => {}
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            b'<' => depth += 1,
            b'>' if i > 0 && matches!(bytes[i - 1], b'-' | b'=') => {}
            b'>' => depth -= 1,
            b';' | b',' if depth <= 0 => return i + 1,
            _ => {}
        }
        i += 1;
    }
    bytes.len()
}

/// Every path that starts with `crate::`, `super::` or `self::` in `code`, as module paths
/// from the crate root (identifier segments only; a `{` ends the path).
fn imported_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    let bytes = code.as_bytes();
    let mut out = Vec::new();
    for start in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
                continue;
            }
            // `self` is the file's own module (a `mod.rs` file is its folder's module).
            let mut path: Vec<String> = match start {
                "crate::" => Vec::new(),
                "super::" => module[..module.len().saturating_sub(1)].to_vec(),
                _ => module.to_vec(),
            };
            let rest = &code[from..];
            let segment_text: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            path.extend(
                segment_text
                    .split("::")
                    .filter(|s| !s.is_empty())
                    .map(str::to_string),
            );
            out.push(path);
        }
    }
    out
}

/// For each file, the files its non-test code imports (the longest module prefix of each
/// path that is a file).
fn file_imports() -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut graph = BTreeMap::new();
    for file in files {
        let Some(code) = code_of(&file) else { continue };
        let module = module_of(&file);
        let mut targets = BTreeSet::new();
        for path in imported_paths(&code, &module) {
            let target = (1..=path.len()).rev().find_map(|n| file_of(&path[..n]));
            if let Some(t) = target
                && t != file
            {
                targets.insert(t);
            }
        }
        graph.insert(file, targets);
    }
    graph
}

fn top_module(file: &Path) -> String {
    module_of(file).first().cloned().unwrap_or_default()
}

#[test]
fn every_module_imports_only_the_layers_below_it() {
    let mut violations = Vec::new();
    for (file, targets) in file_imports() {
        let from = top_module(&file);
        if from.is_empty() || from == TESTING {
            continue;
        }
        let Some(may) = allowed(&from) else {
            violations.push(format!("{}: module '{from}' has no layer", file.display()));
            continue;
        };
        for target in targets {
            let to = top_module(&target);
            if to.is_empty() || to == from || may.contains(&to.as_str()) {
                continue;
            }
            violations.push(format!(
                "{} imports {} ('{from}' may not import '{to}')",
                file.display(),
                target.display()
            ));
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn no_file_imports_itself_through_others() {
    let graph = file_imports();
    // Depth-first search with colours; a grey target is a cycle.
    #[derive(Clone, Copy, PartialEq)]
    enum Colour {
        White,
        Grey,
        Black,
    }
    let mut colour: BTreeMap<&PathBuf, Colour> = graph.keys().map(|k| (k, Colour::White)).collect();
    let mut cycles = Vec::new();
    fn visit<'g>(
        node: &'g PathBuf,
        graph: &'g BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        colour: &mut BTreeMap<&'g PathBuf, Colour>,
        stack: &mut Vec<&'g PathBuf>,
        cycles: &mut Vec<String>,
    ) {
        colour.insert(node, Colour::Grey);
        stack.push(node);
        for next in graph.get(node).into_iter().flatten() {
            match colour.get(next).copied().unwrap_or(Colour::Black) {
                Colour::White => visit(next, graph, colour, stack, cycles),
                Colour::Grey => {
                    let from = stack.iter().position(|n| *n == next).unwrap_or(0);
                    let names: Vec<String> = stack[from..]
                        .iter()
                        .map(|p| p.strip_prefix(src()).unwrap_or(p).display().to_string())
                        .collect();
                    cycles.push(names.join(" -> "));
                }
                Colour::Black => {}
            }
        }
        stack.pop();
        colour.insert(node, Colour::Black);
    }
    for node in graph.keys() {
        if colour[node] == Colour::White {
            visit(node, &graph, &mut colour, &mut Vec::new(), &mut cycles);
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

/// The check itself sees an import: the renderer's tracer imports the surface.
#[test]
fn the_import_scan_sees_known_imports() {
    let graph = file_imports();
    let intersect = src().join("render/intersect.rs");
    assert!(graph[&intersect].contains(&src().join("surface.rs")));
    assert!(!allowed("render").expect("a layer").contains("schemes"));
    assert!(allowed("app").expect("a layer").contains("error"));
    let macro_patch = src().join("schemes/hb/macro_patch.rs");
    assert!(graph[&macro_patch].contains(&src().join("schemes/hb/energy.rs")));
}

/// Only the gated items are left out: code after a test module, a gated field and a gated
/// function is still scanned, and an import there is seen.
#[test]
fn test_items_are_skipped_and_nothing_else() {
    let code = "use crate::surface::Patch;\n\
        struct Hole {\n    #[cfg(test)]\n    ring: Vec<(A, B)>,\n    #[cfg(test)]\n    map: HashMap<K, V>,\n    kept: crate::bezier::X,\n}\n\
        #[cfg(test)]\nfn probe(a: u8) -> crate::metrics::Y { let s = \"}\"; let c = '}'; if a < 2 { } }\n\
        fn after() { crate::mesh::Mesh::new(); }\n\
        #[cfg(test)]\nmod tests {\n    use crate::testing::Rng;\n    fn f() { if 1 > 0 {} }\n}\n\
        fn tail() -> crate::geom::Z { }\n";
    let kept = without_test_items(code);
    let paths = imported_paths(&kept, &["schemes".to_string()]);
    let firsts: Vec<&str> = paths.iter().map(|p| p[0].as_str()).collect();
    assert_eq!(firsts, ["surface", "bezier", "mesh", "geom"], "{kept}");
    assert!(kept.contains("fn tail") && !kept.contains("HashMap") && !kept.contains("probe"));
}

/// The lines of `code` where `#[cfg(test)]` gates something other than a module (a field, a
/// function, a method, a `use`): 1-based, with the start of what it gates. Further attributes
/// after the gate and a visibility before `mod` are allowed; `code` has no comments.
fn gates_on_non_modules(code: &str) -> Vec<(usize, String)> {
    const GATE: &str = "#[cfg(test)]";
    let mut found = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find(GATE) {
        let start = from + at;
        from = start + GATE.len();
        let mut rest = code[from..].trim_start();
        while rest.starts_with("#[") {
            rest = rest
                .find(']')
                .map_or("", |end| rest[end + 1..].trim_start());
        }
        let item = rest;
        for visibility in ["pub(crate) ", "pub(super) ", "pub "] {
            rest = rest.strip_prefix(visibility).unwrap_or(rest);
        }
        if !rest.starts_with("mod ") {
            let rest = item;
            let line = code[..start].matches('\n').count() + 1;
            let gated = rest.lines().next().unwrap_or("").trim().to_string();
            found.push((line, gated));
        }
    }
    found
}

/// Test-only code lives in test modules: in `src/`, `#[cfg(test)]` gates `mod` items only, so
/// no struct changes shape under test and no production file holds test-only functions.
#[test]
fn only_modules_are_gated_by_cfg_test() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    files.sort();
    let mut offenders = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).expect("read source");
        for (line, gated) in gates_on_non_modules(&without_comments(&text)) {
            let name = file.strip_prefix(src()).unwrap_or(file).display();
            offenders.push(format!("src/{name}:{line}: {gated}"));
        }
    }
    assert!(
        offenders.is_empty(),
        "#[cfg(test)] on items other than modules (move them into the test module):\n{}",
        offenders.join("\n")
    );
}

/// The check sees a gated field, function and method, and lets gated modules through.
#[test]
fn gates_on_non_modules_are_found() {
    let code = "struct Hole {\n    #[cfg(test)]\n    ring: Vec<A>,\n}\n\
        impl Hole {\n    #[cfg(test)]\n    pub fn eval(&self) {}\n}\n\
        #[cfg(test)]\n#[allow(dead_code)]\nfn probe() {}\n\
        #[cfg(test)]\nmod tests {}\n\
        #[cfg(test)]\npub(crate) mod test_support;\n\
        #[cfg(test)]\n#[path = \"x.rs\"]\nmod other;\n";
    let found = gates_on_non_modules(code);
    let lines: Vec<usize> = found.iter().map(|(l, _)| *l).collect();
    assert_eq!(lines, [2, 6, 9], "{found:?}");
    assert_eq!(found[0].1, "ring: Vec<A>,");
    assert_eq!(found[1].1, "pub fn eval(&self) {}");
}
