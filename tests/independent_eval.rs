//! An independent check of the G1 figures: the exported patch JSON is read with nothing but
//! `serde_json`, every patch is evaluated by the explicit Bernstein sum written out here
//! (no smoothlab code), shared patch edges are found by matching their end points in space,
//! and the normal jumps along them are compared with what `smoothlab::metrics` reports.

use serde_json::Value;
use smoothlab::mesh::Mesh;
use smoothlab::metrics::Metrics;

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// A triangular Bézier patch as read from the JSON: `points[(i, j)]` with k = d − i − j.
struct Tri {
    face: u64,
    degree: usize,
    points: Vec<((usize, usize), V3)>,
}

impl Tri {
    fn from_json(patch: &Value) -> Tri {
        let degree = patch["degree"].as_u64().expect("degree") as usize;
        let raw = patch["points"].as_array().expect("points");
        // The contract's order: i from d down to 0, then j from d − i down to 0.
        let mut multi = Vec::new();
        for i in (0..=degree).rev() {
            for j in (0..=degree - i).rev() {
                multi.push((i, j));
            }
        }
        assert_eq!(multi.len(), raw.len(), "point count of degree {degree}");
        let points = multi
            .into_iter()
            .zip(raw)
            .map(|(ij, p)| {
                let c: Vec<f64> = p
                    .as_array()
                    .expect("xyz")
                    .iter()
                    .map(|x| x.as_f64().expect("f64"))
                    .collect();
                (ij, [c[0], c[1], c[2]])
            })
            .collect();
        Tri {
            face: patch["face"].as_u64().expect("face"),
            degree,
            points,
        }
    }

    fn point(&self, i: usize, j: usize) -> V3 {
        self.points
            .iter()
            .find(|(ij, _)| *ij == (i, j))
            .expect("control point")
            .1
    }

    /// `Σ c(i,j,k) · n!/(i!j!k!) w0^i w1^j w2^k` over i+j+k = n, with `c` given per multi-index.
    fn bernstein_sum(n: usize, w: V3, c: impl Fn(usize, usize, usize) -> V3) -> V3 {
        let mut sum = [0.0; 3];
        for i in 0..=n {
            for j in 0..=n - i {
                let k = n - i - j;
                let basis = factorial(n) / (factorial(i) * factorial(j) * factorial(k))
                    * w[0].powi(i as i32)
                    * w[1].powi(j as i32)
                    * w[2].powi(k as i32);
                let p = c(i, j, k);
                for m in 0..3 {
                    sum[m] += basis * p[m];
                }
            }
        }
        sum
    }

    /// Position at `(u, v)` (barycentric (1−u−v, u, v)).
    fn eval(&self, u: f64, v: f64) -> V3 {
        Self::bernstein_sum(self.degree, [1.0 - u - v, u, v], |i, j, _| self.point(i, j))
    }

    /// `Su × Sv` from the derivative formulas `Su = d Σ (b_{i,j+1,k} − b_{i+1,j,k}) B^{d−1}`,
    /// `Sv = d Σ (b_{i,j,k+1} − b_{i+1,j,k}) B^{d−1}`.
    fn normal(&self, u: f64, v: f64) -> V3 {
        let d = self.degree;
        let w = [1.0 - u - v, u, v];
        let scale = |p: V3| [p[0] * d as f64, p[1] * d as f64, p[2] * d as f64];
        let su = Self::bernstein_sum(d - 1, w, |i, j, _| {
            scale(sub(self.point(i, j + 1), self.point(i + 1, j)))
        });
        let sv = Self::bernstein_sum(d - 1, w, |i, j, _| {
            scale(sub(self.point(i, j), self.point(i + 1, j)))
        });
        cross(su, sv)
    }

    /// `(u, v)` of the point at fraction `s` along edge `e` (corner e to corner e+1).
    fn edge_uv(e: usize, s: f64) -> (f64, f64) {
        let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
        let (a, b) = (corners[e], corners[(e + 1) % 3]);
        (a.0 + (b.0 - a.0) * s, a.1 + (b.1 - a.1) * s)
    }
}

/// The G1 figures recomputed from the JSON alone.
#[derive(Debug)]
struct Independent {
    joints: usize,
    /// Shared edges that run the same way on both patches: an orientation flip.
    flipped: usize,
    between_max: f64,
    inside_max: f64,
    mean: f64,
    gap_max: f64,
}

fn recompute(json: &str) -> Independent {
    let file: Value = serde_json::from_str(json).expect("patch JSON");
    assert_eq!(file["format"], "smoothlab-patches");
    let tris: Vec<Tri> = file["patches"]
        .as_array()
        .expect("patches")
        .iter()
        .map(Tri::from_json)
        .collect();
    // End points of every patch edge (corner e to corner e+1), evaluated once.
    let ends: Vec<[(V3, V3); 3]> = tris
        .iter()
        .map(|t| {
            [0, 1, 2].map(|e| {
                let (a, b) = (Tri::edge_uv(e, 0.0), Tri::edge_uv(e, 1.0));
                (t.eval(a.0, a.1), t.eval(b.0, b.1))
            })
        })
        .collect();
    let all: Vec<V3> = tris
        .iter()
        .flat_map(|t| t.points.iter().map(|p| p.1))
        .collect();
    let size = (0..3)
        .map(|m| {
            let (lo, hi) = all.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                (lo.min(p[m]), hi.max(p[m]))
            });
            (hi - lo).powi(2)
        })
        .sum::<f64>()
        .sqrt();
    let tol = 1e-9 * size;
    // The sample fractions of the metrics contract: i/16 inside, 1/1024 from the ends.
    let fractions: Vec<f64> = (0..17)
        .map(|i| match i {
            0 => 1.0 / 1024.0,
            16 => 1.0 - 1.0 / 1024.0,
            i => i as f64 / 16.0,
        })
        .collect();
    let mut result = Independent {
        joints: 0,
        flipped: 0,
        between_max: 0.0,
        inside_max: 0.0,
        mean: 0.0,
        gap_max: 0.0,
    };
    let (mut sum, mut count) = (0.0, 0usize);
    for a in 0..tris.len() {
        for (ea, &(a0, a1)) in ends[a].iter().enumerate() {
            for b in a + 1..tris.len() {
                for (eb, &(b0, b1)) in ends[b].iter().enumerate() {
                    // Shared edges run in opposite directions on consistently oriented patches;
                    // a same-direction match is an orientation flip and must show as π.
                    let reversed = norm(sub(a0, b1)) <= tol && norm(sub(a1, b0)) <= tol;
                    let same = norm(sub(a0, b0)) <= tol && norm(sub(a1, b1)) <= tol;
                    if !(reversed || same) {
                        continue;
                    }
                    result.joints += 1;
                    result.flipped += usize::from(!reversed);
                    let mut worst: f64 = 0.0;
                    for &s in &fractions {
                        let (ua, va) = Tri::edge_uv(ea, s);
                        let (ub, vb) = Tri::edge_uv(eb, if reversed { 1.0 - s } else { s });
                        let gap = norm(sub(tris[a].eval(ua, va), tris[b].eval(ub, vb)));
                        result.gap_max = result.gap_max.max(gap / size);
                        let (na, nb) = (tris[a].normal(ua, va), tris[b].normal(ub, vb));
                        let angle = norm(cross(na, nb)).atan2(dot(na, nb));
                        worst = worst.max(angle);
                        sum += angle;
                        count += 1;
                    }
                    if tris[a].face == tris[b].face {
                        result.inside_max = result.inside_max.max(worst);
                    } else {
                        result.between_max = result.between_max.max(worst);
                    }
                }
            }
        }
    }
    result.mean = sum / count as f64;
    result
}

/// An irregular closed mesh: an octahedron with its vertices moved off the symmetric places.
const SKEWED_OCTAHEDRON: &str = "\
v 1.1 0.05 -0.1
v -0.9 0.1 0.05
v 0.05 1.2 0.1
v -0.1 -0.8 -0.05
v 0.1 -0.05 1.3
v 0.02 0.1 -0.7
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
";

/// Every polynomial scheme on `mesh`: the independent figures equal the crate's. (Blends are
/// checked from outside through `smoothlab sample`, in tests/cli.rs.)
fn check_mesh(name: &str, mesh: &Mesh) {
    for scheme in smoothlab::schemes::names() {
        let surface = smoothlab::schemes::build(scheme, mesh, &[]).expect("scheme builds");
        if surface.patches.iter().any(|p| p.as_bezier().is_none()) {
            continue;
        }
        let crate_figures = Metrics::measure(&surface, mesh, 0.0);
        let json = smoothlab::export::to_json(&surface).expect("polynomial patches");
        let ours = recompute(&json);
        let what = format!("{scheme} on {name}");
        assert_eq!(
            ours.joints, crate_figures.joints,
            "{what}: joints found by end points"
        );
        let close = |x: f64, y: Option<f64>, figure: &str| {
            let y = y.unwrap_or(0.0);
            assert!(
                (x - y).abs() <= 1e-12,
                "{what} {figure}: independent {x} vs metrics {y}"
            );
        };
        close(
            ours.between_max,
            crate_figures.g1_between_faces_max_rad,
            "G1 between faces",
        );
        close(
            ours.inside_max,
            crate_figures.g1_inside_faces_max_rad,
            "G1 inside faces",
        );
        close(ours.mean, crate_figures.g1_mean_rad, "G1 mean");
        // Gaps are relative to different boxes (control points here, vertices there), so
        // only whether they are at rounding level is compared.
        let crate_gap = crate_figures.g0_max_rel.unwrap_or(0.0);
        assert_eq!(ours.gap_max <= 1e-12, crate_gap <= 1e-12, "{what} G0");
        assert_eq!(ours.flipped, 0, "{what}: patches oriented alike");
        if scheme == "pn" {
            // PN triangles are only C0: the metric must see it (smallest measured on the
            // scenes: 0.164 rad on the torus).
            assert!(ours.between_max > 0.05, "{what}: pn looks G1");
        }
        println!(
            "{what}: {} joints, G1 between {:.3e} inside {:.3e} mean {:.3e} (metrics {:.3e} {:.3e} {:.3e})",
            ours.joints,
            ours.between_max,
            ours.inside_max,
            ours.mean,
            crate_figures.g1_between_faces_max_rad.unwrap_or(0.0),
            crate_figures.g1_inside_faces_max_rad.unwrap_or(0.0),
            crate_figures.g1_mean_rad.unwrap_or(0.0),
        );
    }
}

#[test]
fn exported_json_gives_the_same_g1_figures() {
    let (mesh, _) = Mesh::parse_obj(SKEWED_OCTAHEDRON).expect("valid mesh");
    check_mesh("skewed octahedron", &mesh);
}

#[test]
fn exported_json_gives_the_same_g1_figures_on_every_scene() {
    for scene in smoothlab::mesh::generate::SCENES {
        check_mesh(scene.name, &scene.mesh().expect("valid scene"));
    }
}
