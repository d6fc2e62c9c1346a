//! End to end on open meshes: `hb` and `loop94` build on the scanned bunny with its base cut
//! open and measure G¹ across every interior edge, every G¹ scheme that takes open meshes does
//! so on a mesh where two edges (one interior, one boundary) join the same two vertices; a render of an open surface tints the
//! inside seen through the opening, and a closed one has no tinted pixel.

mod common;

use common::{path_str, scratch, smoothlab, stderr};

fn open_bunny() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny-open.obj").to_string()
}

#[test]
fn hb_and_loop94_are_g1_on_the_open_bunny() {
    let dir = scratch("open_meshes", "metrics");
    for scheme in ["hb", "loop94"] {
        let json = dir.join(format!("{scheme}.json"));
        let out = smoothlab(&[
            "metrics",
            &open_bunny(),
            "--scheme",
            scheme,
            "--json",
            path_str(&json),
        ]);
        assert!(out.status.success(), "{scheme}: {}", stderr(&out));
        let value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
        let m = &value.as_array().expect("a list")[0];
        let g1 = m["g1_between_faces_max_rad"].as_f64().expect("measured");
        let interpolation = m["interp_max_rel"].as_f64().expect("measured");
        assert!(g1 <= 1e-9, "{scheme}: normal jump {g1} rad");
        assert!(
            interpolation <= 1e-12,
            "{scheme}: interpolation {interpolation}"
        );
    }
}

#[test]
fn g1_schemes_are_g1_on_an_octahedron_with_a_fin() {
    use smoothlab::mesh::{Mesh, generate::bad};
    let (positions, faces) = bad::octahedron_with_fin();
    let (mesh, _) = Mesh::from_triangles(positions, faces).expect("repaired");
    let between = |a: u32, b: u32| {
        mesh.edges()
            .iter()
            .filter(|e| (e.a, e.b) == (a, b))
            .map(|e| e.faces.1.is_some())
            .collect::<Vec<_>>()
    };
    // The fin is split off with its own corners: the octahedron's edge stays interior and
    // no second edge joins its two vertices.
    assert_eq!(between(0, 4), [true], "the fin's edge");
    for scheme in ["hb", "loop94", "piper", "nielson", "fang-mann"] {
        let surface = smoothlab::schemes::build(scheme, &mesh, &[]).expect(scheme);
        let m = smoothlab::metrics::Metrics::measure(&surface, &mesh, 0.0);
        let (g0, g1) = (m.g0_max_rel.expect("joints"), m.g1_max_rad.expect("joints"));
        assert!(
            g0 <= smoothlab::tolerance::POSITION_REL && g1 <= smoothlab::tolerance::NORMAL_RAD,
            "{scheme}: G0 {g0:e}, G1 {g1:e}"
        );
    }
}

/// Pixels whose red and blue differ (zebra stripes are grey; the back-face tint is sepia).
fn tinted_pixels(png: &std::path::Path) -> usize {
    let image = image::open(png).expect("PNG").to_rgb8();
    image
        .pixels()
        .filter(|p| i32::from(p[0]) - i32::from(p[2]) > 8)
        .count()
}

#[test]
fn the_inside_of_an_open_surface_is_tinted_in_zebra() {
    let dir = scratch("open_meshes", "tint");
    let render = |mesh: &str, name: &str| {
        let target = dir.join(name);
        let out = smoothlab(&[
            "render",
            mesh,
            "--scheme",
            "hb",
            "--mode",
            "zebra",
            "--eye",
            "-13,-7,20",
            "--target",
            "-0.8,3.8,0.6",
            "--up",
            "0,1,0",
            "--size",
            "64x64",
            "--spp",
            "1",
            "-o",
            path_str(&target),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        tinted_pixels(&dir.join(format!("{name}.png")))
    };
    let closed = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny.obj");
    let open = render(&open_bunny(), "open");
    assert!(open > 20, "{open} tinted pixels on the open bunny");
    assert_eq!(
        render(closed, "closed"),
        0,
        "tinted pixels on the closed bunny"
    );
}
