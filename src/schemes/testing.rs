//! Test support shared by the scheme modules: the meshes every G¹ scheme is measured on and
//! parameter helpers.

use crate::mesh::{Mesh, generate};
use crate::schemes::{Params, SchemeSpec};

/// A validated mesh from generated triangles.
pub fn mesh((positions, faces): generate::Triangles) -> Mesh {
    Mesh::from_triangles(positions, faces)
        .expect("generated mesh is valid")
        .0
}

/// The closed scenes of scenes/ and a closed mesh with a vertex of each valence 3..=16.
pub fn closed_test_meshes() -> Vec<(String, Mesh)> {
    let mut out: Vec<(String, Mesh)> = generate::SCENES
        .iter()
        .map(|s| (s.name.to_string(), s.mesh().expect("scene mesh is valid")))
        .collect();
    for n in 3..=16 {
        let fan = generate::valence_fan(n).expect("valence in range");
        out.push((format!("valence-fan-{n}"), mesh(fan)));
    }
    out
}

/// `spec`'s parameters with the given overrides.
pub fn params(spec: &SchemeSpec, pairs: &[(&str, &str)]) -> Params {
    let user: Vec<(String, String)> = pairs
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    Params::resolve(spec, &user).expect("valid parameters")
}

/// A deterministic uniform number in [0, 1) (LCG), for randomised parameter tests.
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number.
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
