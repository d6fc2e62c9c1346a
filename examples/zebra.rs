//! Render reflection lines (zebra stripes) of a scheme's surface from code and write a PNG.
//!
//! ```text
//! cargo run --release --example zebra               # hb on the deformed icosahedron → zebra.png
//! cargo run --release --example zebra -- loop94 out.png
//! ```

use std::path::PathBuf;

use smoothlab::mesh::{Mesh, generate};
use smoothlab::render::modes::ZebraParams;
use smoothlab::render::output::write_png;
use smoothlab::render::{Mode, RenderJob, RenderSettings};
use smoothlab::schemes;

fn main() -> smoothlab::Result<()> {
    let mut args = std::env::args().skip(1);
    let scheme = args.next().unwrap_or_else(|| "hb".to_string());
    let output = PathBuf::from(args.next().unwrap_or_else(|| "zebra.png".to_string()));

    let (positions, faces) = generate::deformed_icosahedron();
    let (mesh, _report) = Mesh::from_triangles(positions, faces)?;
    let surface = schemes::build(&scheme, &mesh, &[])?;

    // Everything but the surface: image, mode, camera (framed automatically), exact patches.
    let job = RenderJob {
        settings: RenderSettings {
            width: 480,
            height: 480,
            spp: 4,
            mode: Mode::Zebra(ZebraParams {
                stripes: 12.0,
                ..ZebraParams::default()
            }),
            ..RenderSettings::default()
        },
        ..RenderJob::default()
    };
    let (frame, stats) = job.render(&surface, &mesh)?;
    write_png(&frame, &output)?;
    println!(
        "{scheme}: {} rays, {} hits, render {:.0} ms → {}",
        stats.rays,
        stats.hits,
        stats.render_ms,
        output.display()
    );
    Ok(())
}
