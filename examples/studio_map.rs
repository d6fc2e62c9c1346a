//! Writes the built-in studio environment as a lat-long EXR (linear RGB, +Y up, u = 0 at −Z),
//! the convention of `[shaded] environment = "map.exr"`: the same light for renderers that
//! only take maps.
//!
//! ```text
//! cargo run --release --example studio_map -- studio.exr [WIDTH]   # default width 2048
//! ```
//!
//! Each texel holds the studio's radiance at its centre direction.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use smoothlab::render::Environment;

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(output) = args.next() else {
        eprintln!("usage: studio_map OUT.exr [WIDTH]");
        std::process::exit(2);
    };
    let width: usize = match args.next().map(|w| w.parse()) {
        None => 2048,
        Some(Ok(w)) if w >= 2 => w,
        Some(_) => {
            eprintln!("error: WIDTH must be an integer ≥ 2");
            std::process::exit(2);
        }
    };
    let height = width / 2;
    let env = Environment::Studio;
    let texel = |x: usize, y: usize| {
        let (u, v) = (
            (x as f64 + 0.5) / width as f64,
            (y as f64 + 0.5) / height as f64,
        );
        let (phi, theta) = ((u - 0.5) * TAU, v * PI);
        let d = DVec3::new(
            theta.sin() * phi.sin(),
            theta.cos(),
            -theta.sin() * phi.cos(),
        );
        let l = env.radiance(d);
        (l.x as f32, l.y as f32, l.z as f32)
    };
    if let Err(e) = exr::prelude::write_rgb_file(&output, width, height, texel) {
        eprintln!("error: {output}: {e}");
        std::process::exit(1);
    }
}
