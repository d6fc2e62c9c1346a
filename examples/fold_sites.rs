//! Where a scheme's surface turns over its mesh faces: for every face with fold samples, the
//! samples' count, the face corner nearest to them, that vertex's valence and whether it is on
//! the boundary, and the face's smallest angle (slivers). Samples are taken on a grid of 12
//! steps per patch side, finer than the metrics' `folds` (8), so the totals are larger.
//!
//! ```text
//! cargo run --release --example fold_sites -- scenes/bunny.obj hb [name=value ...]
//! ```

use glam::DVec3;
use smoothlab::mesh::Mesh;
use smoothlab::schemes;

fn main() -> smoothlab::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .unwrap_or_else(|| "scenes/bunny.obj".to_string());
    let scheme = args.next().unwrap_or_else(|| "hb".to_string());
    let params: Vec<(String, String)> = args
        .map(|a| schemes::parse_param(&a))
        .collect::<smoothlab::Result<_>>()?;
    let (mesh, _) = Mesh::load(std::path::Path::new(&path))?;
    let surface = schemes::build(&scheme, &mesh, &params)?;
    let positions = mesh.positions();
    let n = 12;
    let mut total = 0;
    println!("face samples corner vertex valence boundary min_angle_deg");
    for patch in &surface.patches {
        let face = mesh.faces()[patch.face as usize];
        let p = face.map(|v| positions[v as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        let mut count = 0;
        let mut weight = DVec3::ZERO;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                if patch.jet(u, v).cross().dot(normal) < 0.0 {
                    count += 1;
                    let d = patch.domain;
                    weight += d[0] * (1.0 - u - v) + d[1] * u + d[2] * v;
                }
            }
        }
        if count == 0 {
            continue;
        }
        total += count;
        let corner = (0..3)
            .max_by(|&a, &b| weight[a].total_cmp(&weight[b]))
            .unwrap_or(0);
        let angle = |k: usize| {
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            (b - a).angle_between(c - a).to_degrees()
        };
        let min_angle = (0..3).map(angle).fold(f64::INFINITY, f64::min);
        let v = face[corner];
        println!(
            "{} {count} {corner} {v} {} {} {min_angle:.2}",
            patch.face,
            mesh.valence(v),
            mesh.is_boundary_vertex(v)
        );
    }
    println!("total {total}");
    Ok(())
}
