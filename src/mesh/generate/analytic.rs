//! Meshes sampled from analytic surfaces (sphere, ellipsoid, torus) together with the exact
//! surface normals at the vertices, to measure how well estimated normals and the schemes
//! reproduce a known surface.

use std::collections::HashMap;
use std::f64::consts::TAU;

use glam::DVec3;

use super::icosahedron;

/// Vertices on an analytic surface, faces between them, and the surface's exact unit normal at
/// every vertex.
#[derive(Clone, Debug)]
pub struct SampledSurface {
    /// Vertex positions (on the surface).
    pub positions: Vec<DVec3>,
    /// Counter-clockwise faces, outward normals.
    pub faces: Vec<[u32; 3]>,
    /// Exact outward unit normal of the surface at each vertex.
    pub normals: Vec<DVec3>,
}

/// The unit sphere as an icosphere: the [`icosahedron`] with every face split into four
/// `level` times, new vertices projected onto the sphere (12 vertices of valence 5, all others
/// valence 6; 20·4^level faces). The exact normal is the position itself.
pub fn sphere(level: u32) -> SampledSurface {
    let (mut positions, mut faces) = icosahedron();
    for _ in 0..level {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
        let mut finer = Vec::with_capacity(4 * faces.len());
        for &[a, b, c] in &faces {
            let mut middle = |u: u32, v: u32| {
                *midpoint.entry((u.min(v), u.max(v))).or_insert_with(|| {
                    let m = (positions[u as usize] + positions[v as usize]).normalize();
                    positions.push(m);
                    positions.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (middle(a, b), middle(b, c), middle(c, a));
            finer.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        faces = finer;
    }
    let normals = positions.clone();
    SampledSurface {
        positions,
        faces,
        normals,
    }
}

/// The ellipsoid x²/a² + y²/b² + z²/c² = 1 with `radii` = (a, b, c): the [`sphere`] of the same
/// level stretched along the axes. At the image (a·s.x, b·s.y, c·s.z) of a sphere point s the
/// exact normal is the gradient (s.x/a, s.y/b, s.z/c), normalised.
pub fn ellipsoid(radii: DVec3, level: u32) -> SampledSurface {
    let sphere = sphere(level);
    SampledSurface {
        positions: sphere.positions.iter().map(|&s| s * radii).collect(),
        normals: sphere
            .positions
            .iter()
            .map(|&s| (s / radii).normalize())
            .collect(),
        faces: sphere.faces,
    }
}

/// The torus ((R + r cos v) cos u, (R + r cos v) sin u, r sin v) sampled on a `major` × `minor`
/// grid of (u, v), each quad split along the same diagonal so that every vertex has valence 6.
/// Vertex `i·minor + j` is at u = 2πi/major, v = 2πj/minor; the exact normal there is
/// (cos u cos v, sin u cos v, sin v). Needs major, minor ≥ 3 (clamped).
pub fn torus(major: u32, minor: u32, major_radius: f64, minor_radius: f64) -> SampledSurface {
    let (major, minor) = (major.max(3), minor.max(3));
    let mut positions = Vec::with_capacity((major * minor) as usize);
    let mut normals = Vec::with_capacity((major * minor) as usize);
    for i in 0..major {
        let u = TAU * f64::from(i) / f64::from(major);
        for j in 0..minor {
            let v = TAU * f64::from(j) / f64::from(minor);
            let normal = DVec3::new(u.cos() * v.cos(), u.sin() * v.cos(), v.sin());
            let centre = DVec3::new(u.cos(), u.sin(), 0.0) * major_radius;
            positions.push(centre + minor_radius * normal);
            normals.push(normal);
        }
    }
    let vertex = |i: u32, j: u32| (i % major) * minor + j % minor;
    let mut faces = Vec::with_capacity(2 * (major * minor) as usize);
    // (u, v) increase counter-clockwise seen from outside, since ∂u × ∂v is the outward normal.
    for i in 0..major {
        for j in 0..minor {
            let (p00, p10, p11, p01) = (
                vertex(i, j),
                vertex(i + 1, j),
                vertex(i + 1, j + 1),
                vertex(i, j + 1),
            );
            faces.extend([[p00, p10, p11], [p00, p11, p01]]);
        }
    }
    SampledSurface {
        positions,
        faces,
        normals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::normals::angle_between;

    #[test]
    fn sphere_samples_lie_on_the_sphere_with_radial_normals() {
        for level in 0..=4 {
            let s = sphere(level);
            assert_eq!(s.faces.len(), 20 * 4usize.pow(level));
            // Euler: V = F/2 + 2 for a closed genus-0 triangle mesh.
            assert_eq!(s.positions.len(), s.faces.len() / 2 + 2);
            for (p, n) in s.positions.iter().zip(&s.normals) {
                assert!((p.length() - 1.0).abs() < 1e-15);
                assert_eq!(p, n);
            }
        }
    }

    #[test]
    fn ellipsoid_samples_satisfy_the_implicit_equation_with_gradient_normals() {
        let radii = DVec3::new(1.0, 0.8, 1.3);
        let e = ellipsoid(radii, 3);
        for (p, n) in e.positions.iter().zip(&e.normals) {
            let q = *p / radii;
            assert!((q.length_squared() - 1.0).abs() < 1e-14, "{p}");
            let gradient = (*p / (radii * radii)).normalize();
            assert!(angle_between(gradient, *n) < 1e-9, "{p}: {n} vs {gradient}");
            assert!((n.length() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn torus_samples_satisfy_the_implicit_equation_with_gradient_normals() {
        let (big, small) = (1.0, 0.4);
        let t = torus(20, 12, big, small);
        assert_eq!((t.positions.len(), t.faces.len()), (240, 480));
        for (p, n) in t.positions.iter().zip(&t.normals) {
            // (√(x²+y²) − R)² + z² = r², gradient ∝ p − R · (x, y, 0)/√(x²+y²).
            let rho = p.truncate().length();
            assert!(((rho - big).powi(2) + p.z * p.z - small * small).abs() < 1e-14);
            let core = DVec3::new(p.x, p.y, 0.0) / rho * big;
            assert!(angle_between(*p - core, *n) < 1e-9, "{p}");
        }
    }
}
