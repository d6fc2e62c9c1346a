//! Build one scheme on a mesh and print its smoothness metrics.
//!
//! ```text
//! cargo run --release --example metrics                 # hb on the embedded deformed icosahedron
//! cargo run --release --example metrics -- piper my.obj # any scheme on an OBJ file
//! ```

use std::path::Path;

use smoothlab::mesh::{Mesh, generate};
use smoothlab::metrics::Metrics;
use smoothlab::schemes;

fn main() -> smoothlab::Result<()> {
    let mut args = std::env::args().skip(1);
    let scheme = args.next().unwrap_or_else(|| "hb".to_string());
    let mesh = match args.next() {
        Some(path) => Mesh::load_obj(Path::new(&path))?.0,
        None => {
            let (positions, faces) = generate::deformed_icosahedron();
            Mesh::from_triangles(positions, faces)?.0
        }
    };
    // Scheme parameters are `name=value` text pairs; none here: the scheme's defaults.
    let (surface, construct_ms) = schemes::build_timed(&scheme, &mesh, &[])?;
    let m = Metrics::measure(&surface, &mesh, construct_ms);
    println!("{} on {} faces: {} patches", m.scheme, m.faces, m.patches);
    let show = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.3e}"));
    println!(
        "  vertex interpolation (rel. to diagonal): {}",
        show(m.interp_max_rel)
    );
    println!(
        "  G0 gap (rel. to diagonal):               {}",
        show(m.g0_max_rel)
    );
    println!(
        "  G1 normal jump, max (rad):               {}",
        show(m.g1_max_rad)
    );
    println!(
        "  curvature jump, max (relative):          {}",
        show(m.curvature_jump_max_rel)
    );
    println!(
        "  measured continuity order:               {}",
        m.continuity_order
            .map_or("-".to_string(), |k| format!("G{k}"))
    );
    Ok(())
}
