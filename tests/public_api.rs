//! The public API is a facade by intent (ARCHITECTURE.md, "Public API"): src/lib.rs declares
//! only the allow-listed public modules, and every other module is private to the crate.

/// The modules a library user may name; everything else is reached through the re-exports.
const PUBLIC_MODULES: [&str; 8] = [
    "export",
    "mesh",
    "metrics",
    "render",
    "schemes",
    "surface",
    "testing",
    "tolerance",
];

#[test]
fn lib_declares_only_the_allowed_public_modules() {
    let lib = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/lib.rs"))
        .expect("src/lib.rs");
    let public: Vec<&str> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|rest| rest.trim_end_matches(';').trim_end_matches(" {"))
        .collect();
    let unexpected: Vec<&&str> = public
        .iter()
        .filter(|m| !PUBLIC_MODULES.contains(m) && **m != "cli")
        .collect();
    assert!(
        unexpected.is_empty(),
        "public modules not in the facade: {unexpected:?}"
    );
    for m in [
        "app", "report", "bezier", "blend", "geom", "progress", "text",
    ] {
        assert!(
            lib.lines().any(|l| l.trim() == format!("mod {m};")),
            "module {m} is not private in src/lib.rs"
        );
    }
}

/// The most public items the facade may have (see [`public_items`]); raise it only in a
/// commit that means to grow the public API.
const PUBLIC_ITEM_BOUND: usize = 249;

/// Public items reachable from src/lib.rs, counted in the source: every top-level `pub` item
/// (fn, struct, enum, const, static, trait, type) of a public module, walked from `pub mod`
/// lines, and every name a `pub use` of such a module re-exports. Modules hidden from the
/// docs (`testing`, `cli`) are not counted. Cheap: no rustdoc run.
fn public_items() -> usize {
    let src = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/src"));
    let mut count = 0;
    let mut files = vec![(src.join("lib.rs"), src.to_path_buf())];
    while let Some((file, dir)) = files.pop() {
        let text = std::fs::read_to_string(&file).expect("module source");
        let mut hidden = false;
        for line in text.lines() {
            if line.starts_with("#[doc(hidden)]") {
                hidden = true;
                continue;
            }
            let was_hidden = std::mem::take(&mut hidden);
            let Some(rest) = line.strip_prefix("pub ") else {
                continue;
            };
            if was_hidden {
                continue;
            }
            if let Some(name) = rest.strip_prefix("mod ") {
                let Some(name) = name.strip_suffix(';') else {
                    continue;
                };
                let flat = dir.join(format!("{name}.rs"));
                let (path, sub) = if flat.exists() {
                    (flat, dir.join(name))
                } else {
                    (dir.join(name).join("mod.rs"), dir.join(name))
                };
                files.push((path, sub));
            } else if let Some(used) = rest.strip_prefix("use ") {
                let names = used.rsplit("::").next().unwrap_or(used);
                count += names.split(',').filter(|n| !n.trim().is_empty()).count();
            } else if [
                "fn ", "struct ", "enum ", "const ", "static ", "trait ", "type ",
            ]
            .iter()
            .any(|k| rest.starts_with(k) || rest.starts_with(&format!("const {k}")))
            {
                count += 1;
            }
        }
    }
    count
}

#[test]
fn public_surface_stays_within_its_bound() {
    let n = public_items();
    assert!(
        n <= PUBLIC_ITEM_BOUND,
        "the public API has {n} items, above the bound {PUBLIC_ITEM_BOUND}: make the new items \
         pub(crate), or raise PUBLIC_ITEM_BOUND in tests/public_api.rs on purpose"
    );
}
