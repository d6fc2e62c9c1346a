//! Relative RMSE of a rendered image against a reference, over the surface's pixels.
//!
//! ```text
//! cargo run --release --example rmse -- TEST.exr REFERENCE.exr [MASK.exr]
//! ```
//!
//! Both images are linear EXRs with channels `R`, `G`, `B` of the same size (smoothlab's or
//! Mitsuba's). The pixels measured are those whose `patch_id` is ≥ 0 in `MASK.exr` (default:
//! the reference; give a smoothlab EXR of the same camera when the reference has no
//! `patch_id`, e.g. Mitsuba's). The figure is
//!
//! `sqrt(mean over pixels and R, G, B of (test − ref)²) / mean over pixels and R, G, B of ref`,
//!
//! i.e. the RMS error relative to the mean reference value, printed with the pixel count and
//! the means of both images over those pixels (for a check of bias).

use std::path::Path;

use exr::prelude::*;

/// The named channels of the first layer of `path`, row-major, and the image size.
fn channels(path: &Path, names: &[&str]) -> std::result::Result<(usize, Vec<Vec<f32>>), String> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let layer = &image.layer_data;
    let size = layer.size.area();
    let planes = names
        .iter()
        .map(|name| {
            layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.to_string() == *name)
                .map(|c| c.sample_data.values_as_f32().collect::<Vec<f32>>())
                .ok_or_else(|| format!("{}: no channel {name}", path.display()))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    Ok((size, planes))
}

fn run() -> std::result::Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if !(2..=3).contains(&args.len()) {
        return Err("usage: rmse TEST.exr REFERENCE.exr [MASK.exr]".into());
    }
    let rgb = ["R", "G", "B"];
    let (n_test, test) = channels(Path::new(&args[0]), &rgb)?;
    let (n_ref, reference) = channels(Path::new(&args[1]), &rgb)?;
    let (n_mask, mask) = channels(Path::new(args.get(2).unwrap_or(&args[1])), &["patch_id"])?;
    if n_test != n_ref || n_ref != n_mask {
        return Err(format!(
            "image sizes differ: {n_test}, {n_ref} and {n_mask} pixels"
        ));
    }
    let (mut err2, mut sum, mut test_sum, mut count) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for i in (0..n_ref).filter(|&i| mask[0][i] >= 0.0) {
        count += 1;
        for c in 0..3 {
            let (x, r) = (f64::from(test[c][i]), f64::from(reference[c][i]));
            err2 += (x - r) * (x - r);
            sum += r;
            test_sum += x;
        }
    }
    if count == 0 || sum <= 0.0 {
        return Err("no surface pixels with light in the reference".into());
    }
    let samples = (3 * count) as f64;
    let rel = (err2 / samples).sqrt() / (sum / samples);
    println!(
        "relative RMSE {rel:.4} over {count} surface pixels (reference mean {:.5}, test mean {:.5})",
        sum / samples,
        test_sum / samples
    );
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
