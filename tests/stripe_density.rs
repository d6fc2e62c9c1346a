//! The zebra mode's default stripe count follows the view: 16 where the model is large on
//! screen, fewer where 16 stripes would be narrower than 12 pixels (render summary and stats
//! JSON say the count); a given count is kept as given.

mod common;

use common::{path_str, scene, scratch, smoothlab, stderr};

/// Renders the shipped bunny's hb zebra at `size` with `extra` flags; stdout and the stats
/// JSON.
fn zebra(dir: &std::path::Path, size: &str, extra: &[&str]) -> (String, serde_json::Value) {
    let stats = dir.join(format!("stats-{size}-{}.json", extra.len()));
    let mesh = scene("bunny.obj");
    let png = dir.join("z.png");
    let args = [
        &[
            "render",
            mesh.as_str(),
            "--scheme",
            "hb",
            "--mode",
            "zebra",
            "--size",
            size,
            "--no-exr",
            "-o",
            path_str(&png),
            "--stats",
            path_str(&stats),
        ][..],
        extra,
    ]
    .concat();
    let out = smoothlab(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let json = std::fs::read_to_string(&stats).expect("stats");
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        serde_json::from_str(&json).expect("stats JSON"),
    )
}

#[test]
fn the_default_stripe_count_follows_the_size_on_screen() {
    let dir = scratch("stripe_density", "sizes");
    let (small_out, small) = zebra(&dir, "128x128", &[]);
    let (large_out, large) = zebra(&dir, "640x640", &[]);
    let small_count = small["zebra_stripes"].as_f64().expect("a chosen count");
    let large_count = large["zebra_stripes"].as_f64().expect("a chosen count");
    assert!(
        (4.0..16.0).contains(&small_count) && small_count.fract() == 0.0,
        "{small_count}"
    );
    assert_eq!(large_count, 16.0);
    assert!(
        small_out.contains(&format!(
            "zebra: {small_count} stripes per turn, chosen from the view"
        )),
        "{small_out}"
    );
    assert!(
        large_out.contains("zebra: 16 stripes per turn"),
        "{large_out}"
    );
    // A given count stays as given, and nothing is said of it.
    let (given_out, given) = zebra(&dir, "128x128", &["--zebra-stripes", "16"]);
    assert!(given.get("zebra_stripes").is_none(), "{given}");
    assert!(!given_out.contains("chosen from the view"), "{given_out}");
}
