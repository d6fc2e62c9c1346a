//! Colour helpers: sRGB transfer, the curvature colour maps (from `colorous`) and per-face
//! colours.

use glam::DVec3;

/// sRGB-encoded value (0..1) to linear light [IEC 61966-2-1].
pub fn srgb_to_linear(c: DVec3) -> DVec3 {
    let f = |x: f64| {
        if x <= 0.04045 {
            x / 12.92
        } else {
            ((x + 0.055) / 1.055).powf(2.4)
        }
    };
    DVec3::new(f(c.x), f(c.y), f(c.z))
}

/// Linear light (0..1, clamped) to the sRGB-encoded value.
pub fn linear_to_srgb(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The colour of a back-face hit on an open surface, from the front-face colour `c`: mostly
/// desaturated, darkened and turned sepia, so that where an open surface shows its other side
/// reads at once in zebra and curvature images (whose front colours are grey stripes and a
/// blue–red map), while the stripes and the curvature's light/dark order stay visible.
pub fn back_face(c: DVec3) -> DVec3 {
    let luma = c.dot(DVec3::new(0.2126, 0.7152, 0.0722));
    (0.25 * c + DVec3::splat(0.75 * luma)) * DVec3::new(0.85, 0.62, 0.38)
}

/// Linear RGB of a `colorous` gradient at `t ∈ [0, 1]` (clamped).
fn gradient(g: colorous::Gradient, t: f64) -> DVec3 {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let c = g.eval_continuous(t);
    srgb_to_linear(DVec3::new(
        f64::from(c.r) / 255.0,
        f64::from(c.g) / 255.0,
        f64::from(c.b) / 255.0,
    ))
}

/// ColorBrewer RdBu, `t = 0` blue, `0.5` white, `1` red, as linear RGB.
pub fn rdbu(t: f64) -> DVec3 {
    gradient(colorous::RED_BLUE, 1.0 - t)
}

/// viridis (perceptually uniform sequential), `t = 0` dark blue to `1` yellow, as linear RGB.
pub fn viridis(t: f64) -> DVec3 {
    gradient(colorous::VIRIDIS, t)
}

/// A colour per face (golden-ratio hue steps so neighbours differ), lighter or darker per
/// piece, as linear RGB.
pub fn face_colour(face: u32, piece: u8) -> DVec3 {
    let hue = fract_golden(face);
    let value = 0.95 - 0.12 * f64::from(piece % 4);
    srgb_to_linear(hsv(hue, 0.55, value))
}

fn fract_golden(i: u32) -> f64 {
    let x = f64::from(i) * 0.618_033_988_749_895;
    x - x.floor()
}

/// HSV (all 0..1) to sRGB-encoded RGB.
fn hsv(h: f64, s: f64, v: f64) -> DVec3 {
    let h6 = h * 6.0;
    let sector = h6.floor();
    let f = h6 - sector;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    match sector as i32 % 6 {
        0 => DVec3::new(v, t, p),
        1 => DVec3::new(q, v, p),
        2 => DVec3::new(p, v, t),
        3 => DVec3::new(p, q, v),
        4 => DVec3::new(t, p, v),
        _ => DVec3::new(v, p, q),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trip() {
        for i in 0..=20 {
            let x = f64::from(i) / 20.0;
            let back = srgb_to_linear(DVec3::splat(linear_to_srgb(x))).x;
            assert!((back - x).abs() < 1e-12, "{x} -> {back}");
        }
        // The standard's reference point: linear 0.5 encodes to about 0.7354.
        assert!((linear_to_srgb(0.5) - 0.735_356_983).abs() < 1e-8);
    }

    #[test]
    fn maps_run_the_right_way() {
        let white = rdbu(0.5);
        assert!(
            white.min_element() > 0.8,
            "RdBu's middle is near white: {white}"
        );
        assert!(rdbu(1.0).x > rdbu(1.0).z, "the top is red");
        assert!(rdbu(0.0).z > rdbu(0.0).x, "the bottom is blue");
        assert_eq!(
            rdbu(f64::NAN),
            white,
            "NaN maps to the middle, never into the image"
        );
        assert!(viridis(1.0).length() > 3.0 * viridis(0.0).length());
    }
}
