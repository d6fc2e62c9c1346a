//! Deterministic sample positions: every random number is a hash of (seed, pixel, sample,
//! dimension), so an image does not depend on the number of threads or the order of tiles.

use glam::DVec3;

/// SplitMix64 finaliser: a fast bijective 64-bit mixer.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform number in `[0, 1)` for (seed, pixel, sample, dimension).
pub fn uniform(seed: u64, pixel: u64, sample: u32, dimension: u32) -> f64 {
    let key = mix(seed ^ 0x9e37_79b9_7f4a_7c15)
        ^ mix(pixel.wrapping_add(0x632b_e59b_d9b4_e019))
        ^ mix((u64::from(sample) << 32 | u64::from(dimension)).wrapping_add(0x8cb9_2ba7_2f3d_8dd7));
    (mix(key) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Samples per pixel the Owen-scrambled Sobol' points cover (the `sobol_burley` limit); later
/// samples of a pixel use [`uniform`].
pub(crate) const SOBOL_SAMPLES: u32 = 1 << 16;

/// Four numbers in `[0, 1)` of dimension set `set` of sample `sample` of pixel `pixel`: the
/// first four dimensions of an Owen-scrambled Sobol' sequence (Burley's hash-based scrambling)
/// whose scramble and shuffle are seeded by (seed, pixel, set), so each set of four dimensions
/// is stratified over a pixel's samples (its 2-D projections are (0, 2)-sequences) and
/// decorrelated from the other sets and pixels ("padding"). Deterministic per (seed, pixel,
/// sample, set), like [`uniform`].
pub(crate) fn sobol_4d(seed: u64, pixel: u64, sample: u32, set: u32) -> [f64; 4] {
    if sample >= SOBOL_SAMPLES {
        return std::array::from_fn(|k| uniform(seed, pixel, sample, 4 * set + k as u32));
    }
    let key = mix(mix(seed ^ 0x5851_f42d_4c95_7f2d) ^ pixel.wrapping_mul(0x2545_f491_4f6c_dd1d))
        ^ mix(u64::from(set).wrapping_add(0x1405_7b7e_f767_814f));
    let key = mix(key);
    let scramble = (key ^ (key >> 32)) as u32;
    sobol_burley::sample_4d(sample, 0, scramble).map(f64::from)
}

/// A direction uniform on the unit sphere for (seed, index): z uniform in [−1, 1] and the
/// azimuth uniform (Archimedes), from dimensions 0 and 1 of sample 0.
pub fn sphere_direction(seed: u64, index: u64) -> DVec3 {
    let z = 2.0 * uniform(seed, index, 0, 0) - 1.0;
    let phi = std::f64::consts::TAU * uniform(seed, index, 0, 1);
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The position in the unit pixel square of sample `s` of `n`, stratified: a jittered m×m grid
/// when `n = m²`, otherwise n-rooks (one sample per row and per column of an n×n grid).
pub(crate) fn pixel_offset(seed: u64, pixel: u64, s: u32, n: u32) -> (f64, f64) {
    let jx = uniform(seed, pixel, s, 0);
    let jy = uniform(seed, pixel, s, 1);
    let m = (f64::from(n).sqrt().round()) as u32;
    if m * m == n {
        let (cx, cy) = (s % m, s / m);
        (
            (f64::from(cx) + jx) / f64::from(m),
            (f64::from(cy) + jy) / f64::from(m),
        )
    } else {
        let row = (u64::from(s) * u64::from(coprime_step(n)) % u64::from(n)) as u32;
        (
            (f64::from(s) + jx) / f64::from(n),
            (f64::from(row) + jy) / f64::from(n),
        )
    }
}

/// A step near n·0.618 that is coprime to n, so `s ↦ s·step mod n` permutes the rows.
fn coprime_step(n: u32) -> u32 {
    let gcd = |mut a: u32, mut b: u32| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    let mut k = ((f64::from(n) * 0.618).round() as u32).max(1);
    while gcd(k, n) != 1 {
        k += 1;
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_is_in_range_and_deterministic() {
        let mut sum = 0.0;
        for i in 0..10_000u64 {
            let x = uniform(7, i, 3, 1);
            assert!((0.0..1.0).contains(&x), "{x}");
            assert_eq!(x, uniform(7, i, 3, 1), "same key, same number");
            sum += x;
        }
        let mean = sum / 10_000.0;
        assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
    }

    /// Dimensions 0 and 1 of a set form a (0, 2)-sequence over a pixel's first 16 samples (one
    /// point in every elementary interval of area 1/16: 4×4 cells, 16×1, 1×16, 8×2, 2×8 strips)
    /// and every dimension alone is stratified (one point in each sixteenth), in every pixel and
    /// set.
    #[test]
    fn sobol_sets_are_stratified() {
        for pixel in [0u64, 7, 12_345] {
            for set in [0u32, 1, 9] {
                let points: Vec<[f64; 4]> = (0..16).map(|s| sobol_4d(3, pixel, s, set)).collect();
                for log_x in 0..=4u32 {
                    let (nx, ny) = (1usize << log_x, 1usize << (4 - log_x));
                    let mut cells = vec![0; 16];
                    for p in &points {
                        let (cx, cy) = ((p[0] * nx as f64) as usize, (p[1] * ny as f64) as usize);
                        cells[cy * nx + cx] += 1;
                    }
                    assert!(
                        cells.iter().all(|&c| c == 1),
                        "pixel {pixel} set {set} {nx}×{ny}: {cells:?}"
                    );
                }
                for k in 0..4 {
                    let mut cells = vec![0; 16];
                    for p in &points {
                        cells[(p[k] * 16.0) as usize] += 1;
                    }
                    assert!(cells.iter().all(|&c| c == 1), "dimension {k}: {cells:?}");
                }
            }
        }
        assert_ne!(
            sobol_4d(3, 0, 0, 0),
            sobol_4d(3, 1, 0, 0),
            "pixels decorrelated"
        );
        assert_ne!(
            sobol_4d(3, 0, 0, 0),
            sobol_4d(3, 0, 0, 1),
            "sets decorrelated"
        );
        assert_eq!(sobol_4d(3, 5, 2, 1), sobol_4d(3, 5, 2, 1), "deterministic");
        let late = sobol_4d(3, 5, SOBOL_SAMPLES + 1, 1);
        assert!(late.iter().all(|x| (0.0..1.0).contains(x)), "{late:?}");
    }

    #[test]
    fn strata_are_each_hit_once() {
        for n in [4u32, 5, 9, 6] {
            let mut cols = vec![0; n as usize];
            let mut rows = vec![0; n as usize];
            let m = (f64::from(n).sqrt().round()) as u32;
            for s in 0..n {
                let (x, y) = pixel_offset(1, 42, s, n);
                if m * m == n {
                    cols[(x * f64::from(m)) as usize + m as usize * (y * f64::from(m)) as usize] +=
                        1;
                    rows[0] += 1;
                } else {
                    cols[(x * f64::from(n)) as usize] += 1;
                    rows[(y * f64::from(n)) as usize] += 1;
                }
            }
            if m * m == n {
                assert!(cols.iter().all(|&c| c == 1), "grid cells of {n}: {cols:?}");
            } else {
                assert!(cols.iter().all(|&c| c == 1), "columns of {n}: {cols:?}");
                assert!(rows.iter().all(|&c| c == 1), "rows of {n}: {rows:?}");
            }
        }
    }
}
