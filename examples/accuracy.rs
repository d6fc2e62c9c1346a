//! How accurately a scheme reproduces the analytic surfaces its mesh was sampled from: the
//! figures that choose the default shape parameters of `hb` and `loop94` (results/defaults.md).
//!
//! ```text
//! cargo run --release --example accuracy                       # hb, default parameters
//! cargo run --release --example accuracy -- piper              # another scheme
//! cargo run --release --example accuracy -- hb gamma0=-1 gamma1=2 beta=0.333333333333333333
//! ```
//!
//! Columns: largest distance to the true surface (absolute; radius 1 for the spheres), largest
//! normal error (rad), largest and RMS mean-curvature error (relative to the largest true |H|),
//! smallest and largest |H| at the mesh vertices, vertices at which the surface has a flat
//! point, and the largest undulation of the boundary-curve network (rad).

use glam::DVec3;
use smoothlab::mesh::{Mesh, generate::analytic};
use smoothlab::metrics::{network_undulation, vertex_curvature};
use smoothlab::schemes;
use smoothlab::testing::report::analytic::{
    Analytic, curvature_error, surface_error, vertex_curvature_error,
};

fn main() -> smoothlab::Result<()> {
    let mut args = std::env::args().skip(1);
    let scheme = args.next().unwrap_or_else(|| "hb".to_string());
    let params: Vec<(String, String)> = args
        .map(|a| schemes::parse_param(&a))
        .collect::<smoothlab::Result<_>>()?;
    let radii = DVec3::new(1.0, 0.8, 1.3);
    let torus = Analytic::Torus {
        major: 1.0,
        minor: 0.4,
    };
    let cases = [
        (
            "sphere-20",
            analytic::sphere(0),
            Analytic::Sphere { radius: 1.0 },
        ),
        (
            "sphere-80",
            analytic::sphere(1),
            Analytic::Sphere { radius: 1.0 },
        ),
        (
            "sphere-320",
            analytic::sphere(2),
            Analytic::Sphere { radius: 1.0 },
        ),
        (
            "sphere-1280",
            analytic::sphere(3),
            Analytic::Sphere { radius: 1.0 },
        ),
        (
            "ellipsoid-80",
            analytic::ellipsoid(radii, 1),
            Analytic::Ellipsoid { radii },
        ),
        (
            "ellipsoid-320",
            analytic::ellipsoid(radii, 2),
            Analytic::Ellipsoid { radii },
        ),
        (
            "ellipsoid-1280",
            analytic::ellipsoid(radii, 3),
            Analytic::Ellipsoid { radii },
        ),
        ("torus-144", analytic::torus(12, 6, 1.0, 0.4), torus),
        ("torus-576", analytic::torus(24, 12, 1.0, 0.4), torus),
        ("torus-2304", analytic::torus(48, 24, 1.0, 0.4), torus),
    ];
    println!(
        "{:<15} {:>9} {:>9} {:>9} {:>9} {:>7} {:>7} {:>4} {:>9}",
        "mesh", "dist", "normal", "H_max", "H_rms", "|H|v_lo", "|H|v_hi", "flat", "undul"
    );
    for (name, sampled, surface_kind) in cases {
        let mesh = Mesh::from_triangles(sampled.positions, sampled.faces)?.0;
        let surface = schemes::build(&scheme, &mesh, &params)?;
        let (dist, _, normal) = surface_error(&surface, &surface_kind);
        let k = curvature_error(&surface, &surface_kind);
        let (_, h_lo, h_hi) = vertex_curvature_error(&surface, mesh.faces(), &surface_kind);
        let flat = vertex_curvature(&surface, mesh.faces(), mesh.positions()).flat_points;
        let undulation = network_undulation(&surface, &mesh).undulation_max_rad;
        println!(
            "{name:<15} {dist:>9.2e} {normal:>9.2e} {:>9.2e} {:>9.2e} {h_lo:>7.3} {h_hi:>7.3} {flat:>4} {undulation:>9.2e}",
            k.mean_max_rel, k.mean_rms_rel
        );
    }
    Ok(())
}
