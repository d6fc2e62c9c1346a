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
