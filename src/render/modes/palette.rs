//! Colour helpers: sRGB transfer, the curvature colour maps (from `colorous`) and per-face
//! colours.

use glam::{DMat3, DVec3};

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

/// Moreland's cool–warm diverging map [Moreland09 cool–warm]: `t = 0` blue (sRGB 59, 76,
/// 192), `0.5` a neutral grey of CIELAB lightness 88 (sRGB 221), `1` red (180, 4, 38),
/// interpolated in his polar CIELAB coordinates Msh (magnitude, saturation, hue) through the
/// unsaturated middle, with the hue of the unsaturated end spun as his `AdjustHue`
/// prescribes. Its middle is grey, not white, so that zero stays visible on a white page; as
/// linear RGB.
pub fn cool_warm(t: f64) -> DVec3 {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let cool = msh_of(srgb_to_linear(DVec3::new(59.0, 76.0, 192.0) / 255.0));
    let warm = msh_of(srgb_to_linear(DVec3::new(180.0, 4.0, 38.0) / 255.0));
    linear_of_msh(interpolate_msh(cool, warm, t))
}

/// sRGB primaries and D65 white: linear RGB to CIE XYZ, by rows [IEC 61966-2-1].
const RGB_TO_XYZ: [[f64; 3]; 3] = [
    [0.412_456_4, 0.357_576_1, 0.180_437_5],
    [0.212_672_9, 0.715_152_2, 0.072_175_0],
    [0.019_333_9, 0.119_192_0, 0.950_304_1],
];

/// [`RGB_TO_XYZ`] as a matrix.
fn rgb_to_xyz() -> DMat3 {
    DMat3::from_cols_array_2d(&RGB_TO_XYZ).transpose()
}

/// The white point of CIELAB: XYZ of linear RGB (1, 1, 1), so that greys have a = b = 0.
fn white() -> DVec3 {
    rgb_to_xyz() * DVec3::ONE
}

/// CIELAB's `f` and its inverse.
fn lab_f(x: f64) -> f64 {
    const D: f64 = 6.0 / 29.0;
    if x > D * D * D {
        x.cbrt()
    } else {
        x / (3.0 * D * D) + 4.0 / 29.0
    }
}

fn lab_f_inverse(y: f64) -> f64 {
    const D: f64 = 6.0 / 29.0;
    if y > D {
        y * y * y
    } else {
        3.0 * D * D * (y - 4.0 / 29.0)
    }
}

/// CIELAB lightness `L*` of a linear RGB colour.
pub fn lightness(c: DVec3) -> f64 {
    116.0 * lab_f((rgb_to_xyz() * c).y / white().y) - 16.0
}

/// Msh (magnitude, saturation angle, hue angle) of a linear RGB colour [Moreland09 Msh].
fn msh_of(c: DVec3) -> DVec3 {
    let xyz = rgb_to_xyz() * c / white();
    let (fx, fy, fz) = (lab_f(xyz.x), lab_f(xyz.y), lab_f(xyz.z));
    let (l, a, b) = (116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
    let m = (l * l + a * a + b * b).sqrt();
    DVec3::new(m, (l / m).clamp(-1.0, 1.0).acos(), b.atan2(a))
}

/// Linear RGB of Msh coordinates.
fn linear_of_msh(msh: DVec3) -> DVec3 {
    let (m, s, h) = (msh.x, msh.y, msh.z);
    let (l, a, b) = (m * s.cos(), m * s.sin() * h.cos(), m * s.sin() * h.sin());
    let fy = (l + 16.0) / 116.0;
    let xyz = DVec3::new(
        lab_f_inverse(fy + a / 500.0),
        lab_f_inverse(fy),
        lab_f_inverse(fy - b / 200.0),
    ) * white();
    rgb_to_xyz().inverse() * xyz
}

/// Moreland's interpolation from `a` to `b` at `t` [Moreland09 Msh]: through an unsaturated
/// middle of magnitude at least 88 when both ends are saturated and their hues differ by more
/// than 60°, the unsaturated end's hue spun towards the saturated one.
fn interpolate_msh(mut a: DVec3, mut b: DVec3, mut t: f64) -> DVec3 {
    const SATURATED: f64 = 0.05;
    if a.y > SATURATED && b.y > SATURATED && (a.z - b.z).abs() > std::f64::consts::FRAC_PI_3 {
        let middle = DVec3::new(a.x.max(b.x).max(88.0), 0.0, 0.0);
        if t < 0.5 {
            b = middle;
            t *= 2.0;
        } else {
            a = middle;
            t = 2.0 * t - 1.0;
        }
    }
    if a.y < SATURATED && b.y > SATURATED {
        a.z = spun_hue(b, a.x);
    } else if b.y < SATURATED && a.y > SATURATED {
        b.z = spun_hue(a, b.x);
    }
    a + (b - a) * t
}

/// The hue an unsaturated colour of magnitude `m` takes next to the saturated `saturated`
/// (Moreland's `AdjustHue`).
fn spun_hue(saturated: DVec3, m: f64) -> f64 {
    let (ms, s, h) = (saturated.x, saturated.y, saturated.z);
    if ms >= m {
        return h;
    }
    let spin = s * (m * m - ms * ms).sqrt() / (ms * s.sin());
    if h > -std::f64::consts::FRAC_PI_3 {
        h + spin
    } else {
        h - spin
    }
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

    fn srgb8(c: DVec3) -> [f64; 3] {
        [c.x, c.y, c.z].map(|x| linear_to_srgb(x) * 255.0)
    }

    /// The cool–warm map's ends are Moreland's two colours, its middle his neutral grey of
    /// lightness 88, well apart from white (L* = 100); lightness rises to the middle and falls
    /// after it, and the blue half stays blue, the red half red.
    #[test]
    fn cool_warm_runs_from_blue_through_grey_to_red() {
        for (t, want) in [(0.0, [59.0, 76.0, 192.0]), (1.0, [180.0, 4.0, 38.0])] {
            let got = srgb8(cool_warm(t));
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() < 1e-9, "t = {t}: {got:?}");
            }
        }
        let middle = cool_warm(0.5);
        assert!((lightness(middle) - 88.0).abs() < 1e-9, "{middle}");
        assert!(
            (middle.x - middle.y).abs() < 1e-12 && (middle.y - middle.z).abs() < 1e-12,
            "neutral: {middle}"
        );
        assert!(
            (srgb8(middle)[0] - 221.0).abs() < 0.5,
            "{:?}",
            srgb8(middle)
        );
        assert!(lightness(DVec3::ONE) - lightness(middle) > 11.0);
        assert!((lightness(DVec3::ONE) - 100.0).abs() < 1e-9);
        let steps: Vec<f64> = (0..=40)
            .map(|k| lightness(cool_warm(f64::from(k) / 40.0)))
            .collect();
        assert!(steps[..=20].windows(2).all(|w| w[1] > w[0]), "{steps:?}");
        assert!(steps[20..].windows(2).all(|w| w[1] < w[0]), "{steps:?}");
        for k in 0..20 {
            let (blue, red) = (
                cool_warm(f64::from(k) / 40.0),
                cool_warm(1.0 - f64::from(k) / 40.0),
            );
            assert!(blue.z > blue.x && red.x > red.z, "{k}: {blue} {red}");
        }
        assert_eq!(cool_warm(f64::NAN), middle);
    }
}
