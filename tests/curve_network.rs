//! The curve-network comparison of HB00 §9: on the icosahedron with α = 1, β = 0.1, Loop's
//! network undulates (Fig. 14 left) while Hahmann–Bonneau's with γ = (−3.7, 4.6, 0.1) does not
//! (Fig. 14 right); and Fig. 2's point: a smaller α removes Loop's undulation but no longer
//! interpolates the vertices.

use smoothlab::mesh::{Mesh, generate};
use smoothlab::metrics::Metrics;
use smoothlab::schemes;

fn measure(mesh: &Mesh, scheme: &str, params: &[(&str, &str)]) -> Metrics {
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    let surface = schemes::build(scheme, mesh, &params).expect("builds");
    Metrics::measure(&surface, mesh, 0.0)
}

fn icosahedron() -> Mesh {
    smoothlab::testing::mesh(generate::icosahedron())
}

#[test]
fn figure_14_loop_undulates_and_hb_does_not() {
    let mesh = icosahedron();
    let fig14 = [
        ("beta", "0.1"),
        ("gamma0", "-3.7"),
        ("gamma1", "4.6"),
        ("gamma2", "0.1"),
    ];
    let hb = measure(&mesh, "hb", &fig14);
    let lp = measure(&mesh, "loop94", &[("alpha", "1"), ("beta", "0.1")]);
    eprintln!(
        "undulation: loop94 {:.3e} rad ({} inflections), hb {:.3e} rad ({} inflections)",
        lp.network_undulation_max_rad,
        lp.network_inflections_max,
        hb.network_undulation_max_rad,
        hb.network_inflections_max
    );
    assert!(lp.network_inflections_max >= 2);
    assert_eq!(hb.network_inflections_max, 0);
    assert!(lp.network_undulation_max_rad > 0.1);
    assert!(hb.network_undulation_max_rad < 1e-9);
    // Both interpolate.
    assert!(lp.interp_max_rel.unwrap() < 1e-12);
    assert!(hb.interp_max_rel.unwrap() < 1e-12);
}

#[test]
fn figure_2_smaller_alpha_removes_loops_undulation_but_does_not_interpolate() {
    let mesh = icosahedron();
    let interpolating = measure(&mesh, "loop94", &[("alpha", "1"), ("beta", "0.1")]);
    let approximating = measure(&mesh, "loop94", &[("alpha", "0.6"), ("beta", "0.1")]);
    eprintln!(
        "loop94 α=1: undulation {:.3e}, α=0.6: undulation {:.3e}, interpolation error {:.3e}",
        interpolating.network_undulation_max_rad,
        approximating.network_undulation_max_rad,
        approximating.interp_max_rel.unwrap()
    );
    assert!(approximating.network_undulation_max_rad < interpolating.network_undulation_max_rad);
    assert!(approximating.interp_max_rel.unwrap() > 1e-3);
}
