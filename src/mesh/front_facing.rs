//! Front-facing vertex normals: a unit normal at a vertex that every face around it sees from
//! its front side, `n · n_f ≥ μ` for the unit normal `n_f` of every incident face.
//!
//! A surface that interpolates the vertex with normal `n` has, near the vertex, its normal
//! close to `n`; over a face with `n · n_f < 0` it then turns over its face (its normal points
//! against the face's), and a construction that projects the face's edges into the tangent
//! plane gets a corner of the wrong orientation. Estimated normals (angle-weighted, a ring's
//! Fourier plane, a file's `vn`) can point that way at slivers, spikes and near-folds of
//! scanned meshes. Where the estimate is front-facing it is kept; otherwise it is replaced by
//! the front-facing direction closest to it: the point nearest to the estimate on the sphere
//! in the intersection of the caps `n · n_f ≥ μ` — a spherically convex set, so the nearest
//! point is the estimate itself, the nearest point of one cap's circle, or a corner where two
//! circles meet, and the best feasible one of these candidates is it.
//!
//! The margin `μ` is [`FRONT_MARGIN`], or the largest decade down to [`MIN_FRONT_MARGIN`] that
//! the one-ring admits. A one-ring that admits none folds over itself (no open hemisphere
//! holds its face normals, e.g. a flattened ring with faces on both sides of a sheet): no
//! surface through the vertex avoids a fold there.

use glam::DVec3;

/// The margin a front-facing normal keeps from every incident face's plane: `n · n_f ≥ 1e-3`,
/// i.e. at least 0.057° off the face's plane. An estimate closer to a face's plane than this is
/// moved by about the shortfall, so that corner tangents projected into the tangent plane stay
/// well apart (a normal almost in a face's plane makes that face's corner nearly singular).
pub(crate) const FRONT_MARGIN: f64 = 1e-3;

/// The smallest margin accepted before a one-ring counts as folded over itself: above the
/// frame-area bound of the boundary-blend schemes (1e-8 of `|e|²`), so their frames stay
/// regular, and far above the rounding of unit normals (1e-16).
pub(crate) const MIN_FRONT_MARGIN: f64 = 1e-7;

/// What `test_support::front_facing` did with a vertex's estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum FrontFacing {
    /// The estimate is front-facing by [`FRONT_MARGIN`]: kept.
    Kept,
    /// Replaced by the closest direction front-facing by `margin`, `angle` (rad) away.
    Moved {
        /// The new unit normal.
        normal: DVec3,
        /// The margin it keeps (a decade from [`FRONT_MARGIN`] to [`MIN_FRONT_MARGIN`]).
        margin: f64,
        /// Its angle to the estimate.
        angle: f64,
    },
    /// No direction is front-facing by [`MIN_FRONT_MARGIN`]: the one-ring folds over itself.
    Folded,
}

/// The smallest `n · n_f` over the unit face normals `faces`.
pub(crate) fn min_cosine(n: DVec3, faces: &[DVec3]) -> f64 {
    faces
        .iter()
        .map(|f| n.dot(*f))
        .fold(f64::INFINITY, f64::min)
}

/// `test_support::front_facing` with the margin `wanted` (in `[MIN_FRONT_MARGIN, 1)`) in place of
/// [`FRONT_MARGIN`]: the estimate is kept if `n · n_f ≥ wanted` for every face, else moved to
/// the closest direction keeping `wanted`, or the largest decade below it down to
/// [`MIN_FRONT_MARGIN`] that the one-ring admits.
pub(crate) fn front_facing_by(estimate: DVec3, faces: &[DVec3], wanted: f64) -> FrontFacing {
    if min_cosine(estimate, faces) >= wanted {
        return FrontFacing::Kept;
    }
    let mut margin = wanted;
    while margin >= MIN_FRONT_MARGIN * 0.999 {
        if let Some(normal) = closest_in_caps(estimate, faces, margin) {
            return FrontFacing::Moved {
                normal,
                margin,
                angle: normal.cross(estimate).length().atan2(normal.dot(estimate)),
            };
        }
        margin /= 10.0;
    }
    FrontFacing::Folded
}

/// The unit vector closest to `n0` with `n · f ≥ margin` for every `f` in `faces`, or `None`
/// if there is none. Candidates: `n0`, the point of each circle `n · f = margin` nearest to
/// `n0`, and the points where two circles meet; the feasible candidate nearest to `n0` is the
/// answer (the feasible set is spherically convex, so its nearest point is one of them).
fn closest_in_caps(n0: DVec3, faces: &[DVec3], margin: f64) -> Option<DVec3> {
    // Candidates are computed to a few ulps; the slack keeps those exactly on a circle.
    let feasible = |n: DVec3| min_cosine(n, faces) >= margin * (1.0 - 1e-9);
    let mut best: Option<DVec3> = None;
    let mut offer = |n: DVec3| {
        if n.is_finite() && feasible(n) && best.is_none_or(|b| n.dot(n0) > b.dot(n0)) {
            best = Some(n);
        }
    };
    offer(n0);
    let lift = (1.0 - margin * margin).sqrt();
    for &f in faces {
        // n0's direction within the circle's plane (any one if n0 is ±f).
        let along = (n0 - n0.dot(f) * f)
            .try_normalize()
            .unwrap_or_else(|| f.any_orthonormal_vector());
        offer((margin * f + lift * along).normalize());
    }
    for (i, &f) in faces.iter().enumerate() {
        for &g in &faces[i + 1..] {
            let axis = f.cross(g);
            let sine_squared = axis.length_squared();
            if sine_squared <= 1e-24 {
                continue;
            }
            // n = a (f + g) + c (f × g) with n · f = n · g = margin and |n| = 1.
            let a = margin / (1.0 + f.dot(g));
            let rest = 1.0 - a * a * (f + g).length_squared();
            if rest < 0.0 {
                continue;
            }
            let c = (rest / sine_squared).sqrt();
            for sign in [1.0, -1.0] {
                offer((a * (f + g) + sign * c * axis).normalize());
            }
        }
    }
    best
}

/// Vertex normals made front-facing over a whole mesh ([`front_facing_normals`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FrontFacingNormals {
    /// One unit normal per vertex: the estimate where it was front-facing, else the closest
    /// front-facing direction; the estimate at vertices in `folded`.
    pub normals: Vec<DVec3>,
    /// Vertices whose estimate was replaced, with the angle moved (rad), in vertex order.
    pub moved: Vec<(u32, f64)>,
    /// Vertices whose one-ring folds over itself (no front-facing direction), in order.
    pub folded: Vec<u32>,
}

/// The unit normal of every face (zero for a face of zero area, which constrains nothing).
fn face_normals(positions: &[DVec3], faces: &[[u32; 3]]) -> Vec<DVec3> {
    faces
        .iter()
        .map(|f| {
            let p = f.map(|v| positions[v as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
        })
        .collect()
}

/// The unit vertex normals `estimate` (one per vertex of `positions`) made front-facing for
/// the faces around each vertex.
pub(crate) fn front_facing_normals(
    positions: &[DVec3],
    faces: &[[u32; 3]],
    estimate: &[DVec3],
) -> FrontFacingNormals {
    front_facing_normals_by(positions, faces, estimate, FRONT_MARGIN)
}

/// [`front_facing_normals`] with the margin `wanted` ([`front_facing_by`]).
pub(crate) fn front_facing_normals_by(
    positions: &[DVec3],
    faces: &[[u32; 3]],
    estimate: &[DVec3],
    wanted: f64,
) -> FrontFacingNormals {
    let unit = face_normals(positions, faces);
    let mut worst = vec![f64::INFINITY; positions.len()];
    for (face, n) in faces.iter().zip(&unit) {
        for &v in face {
            if *n != DVec3::ZERO {
                worst[v as usize] = worst[v as usize].min(estimate[v as usize].dot(*n));
            }
        }
    }
    // The face normals around the vertices whose estimate falls short, in face order.
    let mut around: std::collections::BTreeMap<u32, Vec<DVec3>> = worst
        .iter()
        .enumerate()
        .filter(|(_, w)| **w < wanted)
        .map(|(v, _)| (v as u32, Vec::new()))
        .collect();
    for (face, n) in faces.iter().zip(&unit) {
        for v in face {
            if let Some(list) = around.get_mut(v)
                && *n != DVec3::ZERO
            {
                list.push(*n);
            }
        }
    }
    let mut result = FrontFacingNormals {
        normals: estimate.to_vec(),
        moved: Vec::new(),
        folded: Vec::new(),
    };
    for (v, ring) in around {
        match front_facing_by(estimate[v as usize], &ring, wanted) {
            FrontFacing::Kept => {}
            FrontFacing::Moved { normal, angle, .. } => {
                result.normals[v as usize] = normal;
                result.moved.push((v, angle));
            }
            FrontFacing::Folded => result.folded.push(v),
        }
    }
    result
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    /// The unit `estimate` made front-facing for the unit normals `faces` of the faces around its
    /// vertex (see the module documentation).
    pub(crate) fn front_facing(estimate: DVec3, faces: &[DVec3]) -> FrontFacing {
        front_facing_by(estimate, faces, FRONT_MARGIN)
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use crate::mesh::generate;
    use crate::testing::Rng;

    fn unit(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z).normalize()
    }

    /// Directions on a fine spiral over the sphere (Fibonacci lattice), for brute-force checks.
    fn sphere_directions(count: usize) -> Vec<DVec3> {
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        (0..count)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
                let r = (1.0 - z * z).sqrt();
                let phi = golden * i as f64;
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect()
    }

    #[test]
    fn a_front_facing_estimate_is_kept() {
        let faces = [
            unit(0.3, 0.0, 1.0),
            unit(-0.2, 0.4, 1.0),
            unit(0.0, -0.5, 1.0),
        ];
        assert_eq!(front_facing(DVec3::Z, &faces), FrontFacing::Kept);
        for (positions, faces) in [generate::octahedron(), generate::mixed_valence()] {
            let estimate = crate::mesh::normals::angle_weighted(&positions, &faces).unwrap();
            let front = front_facing_normals(&positions, &faces, &estimate);
            assert_eq!(front.normals, estimate);
            assert!(front.moved.is_empty() && front.folded.is_empty());
        }
    }

    /// A ring whose faces lean 60° to +x and one face leaning 80° to −x: the face-weighted
    /// mean leans to +x and sees the last face from behind; the closest front-facing normal
    /// lies on that face's circle `n · f = μ`, in the plane of the estimate and the face.
    #[test]
    fn a_normal_behind_a_face_moves_onto_that_face_circle() {
        let lean = |deg: f64, y: f64| {
            let a = deg.to_radians();
            DVec3::new(a.sin(), y, a.cos()).normalize()
        };
        let back = lean(-80.0, 0.0);
        let faces = [lean(60.0, 0.2), lean(60.0, -0.2), lean(60.0, 0.0), back];
        let estimate = lean(40.0, 0.0);
        assert!(estimate.dot(back) < 0.0);
        let FrontFacing::Moved {
            normal,
            margin,
            angle,
        } = front_facing(estimate, &faces)
        else {
            panic!("not moved")
        };
        assert_eq!(margin, FRONT_MARGIN);
        assert!((normal.dot(back) - FRONT_MARGIN).abs() <= 1e-15, "{normal}");
        assert!(normal.y.abs() <= 1e-15, "{normal}");
        assert!((normal.length() - 1.0).abs() <= 1e-15);
        // n · back = μ: n leans to x at 90° − 80° − asin(μ) from z.
        let expected = 10f64.to_radians() - FRONT_MARGIN.asin();
        assert!(
            (normal.x.atan2(normal.z) - expected).abs() <= 1e-14,
            "{normal}"
        );
        assert!((angle - (40f64.to_radians() - expected)).abs() <= 1e-14);
    }

    /// Random rings (a few faces, normals spread over up to a hemisphere and beyond) against a
    /// brute-force search over 200k directions: a moved normal keeps its margin, is at least as
    /// close to the estimate as every sampled direction that keeps it, and a ring called folded
    /// has no sampled direction keeping the smallest margin.
    #[test]
    fn the_closest_front_facing_direction_beats_every_sampled_one() {
        let directions = sphere_directions(200_000);
        let mut rng = Rng::new(0x5eed);
        let (mut moved, mut folded) = (0, 0);
        for case in 0..300 {
            let count = 3 + case % 6;
            let spread = 0.3 + 2.8 * rng.next_f64();
            let faces: Vec<DVec3> = (0..count)
                .map(|_| {
                    let (theta, phi) = (
                        spread * rng.next_f64(),
                        std::f64::consts::TAU * rng.next_f64(),
                    );
                    DVec3::new(
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    )
                })
                .collect();
            let estimate = unit(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.5);
            match front_facing(estimate, &faces) {
                FrontFacing::Kept => assert!(min_cosine(estimate, &faces) >= FRONT_MARGIN),
                FrontFacing::Moved { normal, margin, .. } => {
                    moved += 1;
                    assert!((normal.length() - 1.0).abs() <= 1e-15);
                    assert!(
                        min_cosine(normal, &faces) >= margin * (1.0 - 1e-9),
                        "{case}"
                    );
                    let beaten = directions
                        .iter()
                        .filter(|d| min_cosine(**d, &faces) >= margin)
                        .map(|d| d.dot(estimate))
                        .fold(f64::NEG_INFINITY, f64::max);
                    assert!(normal.dot(estimate) >= beaten - 1e-15, "{case}: {beaten}");
                }
                FrontFacing::Folded => {
                    folded += 1;
                    let best = directions
                        .iter()
                        .map(|d| min_cosine(*d, &faces))
                        .fold(f64::NEG_INFINITY, f64::max);
                    assert!(best < MIN_FRONT_MARGIN, "{case}: {best}");
                }
            }
        }
        assert!(moved > 50 && folded > 20, "moved {moved}, folded {folded}");
    }

    /// The octahedron flattened to a sheet (z scaled by 1e-9): the four equator vertices see
    /// faces facing up and down, so their rings fold over themselves; the poles' rings are
    /// fine (their estimates ±z are kept).
    #[test]
    fn a_ring_on_both_sides_of_a_sheet_is_folded() {
        let (mut positions, faces) = generate::octahedron();
        for p in &mut positions {
            p.z *= 1e-9;
        }
        let estimate = crate::mesh::normals::angle_weighted(&positions, &faces).unwrap();
        let front = front_facing_normals(&positions, &faces, &estimate);
        let equator: Vec<u32> = (0..positions.len() as u32)
            .filter(|&v| positions[v as usize].z == 0.0)
            .collect();
        assert_eq!(front.folded, equator);
        assert!(front.moved.is_empty(), "{:?}", front.moved);
    }
}
