//! Writes `scenes/hostile/`: small meshes with what scanned, modelled and exported meshes carry
//! and the papers' meshes do not (non-planar quads, n-gons, non-manifold vertices and edges,
//! slivers and zero-area faces, holes, a flipped face, coordinates far from the origin, a part
//! with flat faces and 90° creases, an assembly of open parts that touch, a UV sphere whose
//! poles have valence 64, a stray vertex far from the rest). Deterministic: the
//! jitter is a hash of the vertex index, so the files are the same on every run.
//!
//! ```text
//! cargo run --release --example hostile_corpus            # writes scenes/hostile/*.obj
//! ```
//!
//! `tests/hostile_corpus.rs` runs every scheme on each file.

use std::f64::consts::PI;
use std::fmt::Write as _;

use glam::DVec3;

/// A polygon mesh: positions and faces of any size, counter-clockwise seen from outside.
struct Polygons {
    positions: Vec<DVec3>,
    faces: Vec<Vec<u32>>,
}

impl Polygons {
    fn new() -> Polygons {
        Polygons {
            positions: Vec::new(),
            faces: Vec::new(),
        }
    }

    fn point(&mut self, p: DVec3) -> u32 {
        self.positions.push(p);
        (self.positions.len() - 1) as u32
    }

    /// Appends `other` (its indices shifted).
    fn append(&mut self, other: Polygons) {
        let base = self.positions.len() as u32;
        self.positions.extend(other.positions);
        self.faces.extend(
            other
                .faces
                .into_iter()
                .map(|f| f.into_iter().map(|i| i + base).collect()),
        );
    }

    fn map(mut self, f: impl Fn(DVec3) -> DVec3) -> Polygons {
        for p in &mut self.positions {
            *p = f(*p);
        }
        self
    }

    fn obj(&self, header: &str) -> String {
        let mut text = String::new();
        for line in header.lines() {
            let _ = writeln!(text, "# {line}");
        }
        let _ = writeln!(
            text,
            "# {} vertices, {} faces; written by `cargo run --release --example hostile_corpus`",
            self.positions.len(),
            self.faces.len()
        );
        for p in &self.positions {
            let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
        }
        for f in &self.faces {
            let corners: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
            let _ = writeln!(text, "f {}", corners.join(" "));
        }
        text
    }
}

/// A deterministic value in [−1, 1] from an index and a salt.
fn jitter(i: u64, salt: u64) -> f64 {
    let mut x = i.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt.wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// A sphere of quads: the cube `[-1, 1]³` with `n × n` quads per side pushed onto the sphere
/// of radius `radius`, each vertex moved radially by up to `bump` (so the quads are not
/// planar) and by `shape(direction)`.
fn quad_sphere(n: u32, radius: f64, bump: f64, salt: u64) -> Polygons {
    let mut mesh = Polygons::new();
    let mut index = std::collections::HashMap::new();
    let axes = [
        (DVec3::X, DVec3::Y, DVec3::Z),
        (-DVec3::X, DVec3::Z, DVec3::Y),
        (DVec3::Y, DVec3::Z, DVec3::X),
        (-DVec3::Y, DVec3::X, DVec3::Z),
        (DVec3::Z, DVec3::X, DVec3::Y),
        (-DVec3::Z, DVec3::Y, DVec3::X),
    ];
    for (normal, a, b) in axes {
        let mut id = |i: u32, j: u32, mesh: &mut Polygons| {
            let s = 2.0 * f64::from(i) / f64::from(n) - 1.0;
            let t = 2.0 * f64::from(j) / f64::from(n) - 1.0;
            let cube = normal + s * a + t * b;
            let key = (cube * 1e6).round().as_i64vec3();
            *index.entry((key.x, key.y, key.z)).or_insert_with(|| {
                let k = mesh.positions.len() as u64;
                let dir = cube.normalize();
                mesh.point(dir * radius * (1.0 + bump * jitter(k, salt)))
            })
        };
        for i in 0..n {
            for j in 0..n {
                let q = [
                    id(i, j, &mut mesh),
                    id(i + 1, j, &mut mesh),
                    id(i + 1, j + 1, &mut mesh),
                    id(i, j + 1, &mut mesh),
                ];
                mesh.faces.push(q.to_vec());
            }
        }
    }
    // Every side's (a, b) was chosen with a × b = normal, so the quads face outward.
    mesh
}

/// A triangulated icosphere of radius 1 (level subdivisions of the icosahedron).
fn icosphere(level: u32) -> Polygons {
    let surface = smoothlab::mesh::generate::analytic::sphere(level);
    Polygons {
        positions: surface.positions,
        faces: surface.faces.iter().map(|f| f.to_vec()).collect(),
    }
}

/// A tube of `columns × rows` quads around the curve `centre(t)`, `t ∈ [0, 1]`, of radius
/// `radius(t)`, open at both ends; `frame(t)` gives two unit vectors across the curve.
fn tube(
    columns: u32,
    rows: u32,
    centre: impl Fn(f64) -> DVec3,
    radius: impl Fn(f64) -> f64,
    frame: impl Fn(f64) -> (DVec3, DVec3),
) -> Polygons {
    let mut mesh = Polygons::new();
    for r in 0..=rows {
        let t = f64::from(r) / f64::from(rows);
        let (e1, e2) = frame(t);
        for c in 0..columns {
            let a = 2.0 * PI * f64::from(c) / f64::from(columns);
            mesh.point(centre(t) + radius(t) * (a.cos() * e1 + a.sin() * e2));
        }
    }
    for r in 0..rows {
        for c in 0..columns {
            let at = |r: u32, c: u32| r * columns + c % columns;
            mesh.faces
                .push(vec![at(r, c), at(r, c + 1), at(r + 1, c + 1), at(r + 1, c)]);
        }
    }
    mesh
}

/// A surface of revolution about z through the profile `(ρ(t), z(t))`, `t ∈ [0, 1]`, with
/// `columns` quads around; open where ρ ≠ 0, closed by a fan where ρ(0) = 0.
fn revolution(columns: u32, rows: u32, profile: impl Fn(f64) -> (f64, f64)) -> Polygons {
    let mut mesh = Polygons::new();
    let (rho0, z0) = profile(0.0);
    let pole = (rho0 == 0.0).then(|| mesh.point(DVec3::new(0.0, 0.0, z0)));
    let first = u32::from(pole.is_some());
    for r in first..=rows {
        let (rho, z) = profile(f64::from(r) / f64::from(rows));
        for c in 0..columns {
            let a = 2.0 * PI * f64::from(c) / f64::from(columns);
            mesh.point(DVec3::new(rho * a.cos(), rho * a.sin(), z));
        }
    }
    let base = u32::from(pole.is_some());
    let at = |r: u32, c: u32| base + (r - first) * columns + c % columns;
    if let Some(pole) = pole {
        for c in 0..columns {
            mesh.faces.push(vec![pole, at(1, c + 1), at(1, c)]);
        }
    }
    for r in first.max(1).min(rows)..rows {
        for c in 0..columns {
            mesh.faces
                .push(vec![at(r, c), at(r + 1, c), at(r + 1, c + 1), at(r, c + 1)]);
        }
    }
    if pole.is_none() {
        for c in 0..columns {
            mesh.faces
                .push(vec![at(0, c), at(1, c), at(1, c + 1), at(0, c + 1)]);
        }
    }
    mesh
}

/// The unit UV sphere of modelling tools: `columns` meridians, `rows` bands of planar quads
/// between the parallels, and a fan of `columns` triangles round each pole (so each pole has
/// valence `columns` beside vertices of valence 4 and 5).
fn uv_sphere(columns: u32, rows: u32) -> Polygons {
    let mut mesh = Polygons::new();
    let north = mesh.point(DVec3::Z);
    for r in 1..rows {
        let polar = PI * f64::from(r) / f64::from(rows);
        for c in 0..columns {
            let a = 2.0 * PI * f64::from(c) / f64::from(columns);
            mesh.point(DVec3::new(
                polar.sin() * a.cos(),
                polar.sin() * a.sin(),
                polar.cos(),
            ));
        }
    }
    let south = mesh.point(-DVec3::Z);
    let at = |r: u32, c: u32| 1 + (r - 1) * columns + c % columns;
    for c in 0..columns {
        mesh.faces.push(vec![north, at(1, c), at(1, c + 1)]);
        mesh.faces
            .push(vec![south, at(rows - 1, c + 1), at(rows - 1, c)]);
    }
    for r in 1..rows - 1 {
        for c in 0..columns {
            mesh.faces
                .push(vec![at(r, c), at(r + 1, c), at(r + 1, c + 1), at(r, c + 1)]);
        }
    }
    mesh
}

/// The closed surface of the voxels `filled(x, y, z)` of a `size` grid, cells of edge `cell`:
/// one planar quad per exposed voxel side.
fn voxels(size: [i32; 3], cell: f64, filled: impl Fn(i32, i32, i32) -> bool) -> Polygons {
    let mut mesh = Polygons::new();
    let mut index = std::collections::HashMap::new();
    let inside = |x: i32, y: i32, z: i32| {
        (0..size[0]).contains(&x)
            && (0..size[1]).contains(&y)
            && (0..size[2]).contains(&z)
            && filled(x, y, z)
    };
    let mut id = |p: [i32; 3], mesh: &mut Polygons| {
        *index.entry(p).or_insert_with(|| {
            mesh.point(cell * DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
        })
    };
    for x in 0..size[0] {
        for y in 0..size[1] {
            for z in 0..size[2] {
                if !inside(x, y, z) {
                    continue;
                }
                for axis in 0..3 {
                    for side in [-1, 1] {
                        let mut n = [x, y, z];
                        n[axis] += side;
                        if inside(n[0], n[1], n[2]) {
                            continue;
                        }
                        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                        let mut base = [x, y, z];
                        if side > 0 {
                            base[axis] += 1;
                        }
                        let corner = |du: i32, dv: i32| {
                            let mut c = base;
                            c[u] += du;
                            c[v] += dv;
                            c
                        };
                        let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                        if side < 0 {
                            quad.reverse();
                        }
                        let face = quad.map(|c| id(c, &mut mesh)).to_vec();
                        mesh.faces.push(face);
                    }
                }
            }
        }
    }
    mesh
}

fn main() -> std::io::Result<()> {
    let dir = std::path::Path::new("scenes/hostile");
    std::fs::create_dir_all(dir)?;
    let mut files: Vec<(&str, String, Polygons)> = Vec::new();

    files.push((
        "quad-blob.obj",
        "A closed blob of 384 non-planar quads (a cube pushed onto a sphere, radii jittered by 4 %)".into(),
        quad_sphere(8, 1.0, 0.04, 1),
    ));

    // n-gons: a twelve-sided prism with twelve-gon caps, one of them concave (a notch).
    let mut prism = Polygons::new();
    let sides = 12u32;
    for level in 0..2 {
        for c in 0..sides {
            let a = 2.0 * PI * f64::from(c) / f64::from(sides);
            let r = if level == 1 && c == 3 { 0.55 } else { 1.0 };
            prism.point(DVec3::new(r * a.cos(), r * a.sin(), 0.8 * f64::from(level)));
        }
    }
    prism.faces.push((0..sides).rev().collect());
    prism.faces.push((sides..2 * sides).collect());
    for c in 0..sides {
        let d = (c + 1) % sides;
        prism.faces.push(vec![c, d, sides + d, sides + c]);
    }
    files.push((
        "ngon-prism.obj",
        "A twelve-sided prism: two twelve-gon caps (the top one concave) and twelve quads".into(),
        prism,
    ));

    // A non-manifold vertex: two bumpy quad spheres touching at one shared vertex.
    let mut pinch = quad_sphere(4, 1.0, 0.03, 2);
    let top = pinch
        .positions
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.x.total_cmp(&b.1.x))
        .map(|(i, p)| (i, *p))
        .unwrap_or((0, DVec3::X));
    let other = quad_sphere(4, 1.0, 0.03, 3);
    let low = other
        .positions
        .iter()
        .copied()
        .min_by(|a, b| a.x.total_cmp(&b.x))
        .unwrap_or(-DVec3::X);
    let shift = top.1 - low;
    pinch.append(other.map(|p| p + shift));
    files.push((
        "pinched-pair.obj",
        "Two closed quad blobs touching at one vertex (a non-manifold vertex once welded)".into(),
        pinch,
    ));

    // A non-manifold edge: an icosphere and a triangular fin of two faces hinged on one of its
    // edges (three faces at that edge).
    let mut fin = icosphere(1);
    let [a, b] = {
        let f = fin.faces[0].clone();
        [f[0], f[1]]
    };
    let mid = 0.5 * (fin.positions[a as usize] + fin.positions[b as usize]);
    let tip = fin.point(mid * 1.8);
    let tip2 = fin.point(mid * 1.8 + 0.3 * (fin.positions[b as usize] - fin.positions[a as usize]));
    fin.faces.push(vec![a, b, tip]);
    fin.faces.push(vec![b, tip2, tip]);
    files.push((
        "finned-sphere.obj",
        "An icosphere with a fin of two triangles hinged on one of its edges (a non-manifold edge)"
            .into(),
        fin,
    ));

    // Slivers and zero-area faces: an icosphere with some edges split very near one end (two
    // slivers each) and one face whose corners are collinear.
    let mut slivers = icosphere(2);
    let count = slivers.faces.len();
    for f in (0..count).step_by(23) {
        let face = slivers.faces[f].clone();
        let (p, q, r) = (face[0], face[1], face[2]);
        let (pp, pq) = (slivers.positions[p as usize], slivers.positions[q as usize]);
        // Split the face (not its neighbour) at a point 2 % along p → q, lifted to the sphere:
        // a T-junction-free sliver fan of two faces.
        let s = slivers.point((pp + 0.02 * (pq - pp)).normalize());
        slivers.faces[f] = vec![p, s, r];
        slivers.faces.push(vec![s, q, r]);
        // Close the crack on the neighbour across p-q by splitting it too.
        if let Some(g) = (0..count).find(|&g| {
            let h = &slivers.faces[g];
            (0..3).any(|k| h[k] == q && h[(k + 1) % 3] == p)
        }) {
            let h = slivers.faces[g].clone();
            let k = (0..3).find(|&k| h[k] == q).unwrap_or(0);
            let o = h[(k + 2) % 3];
            slivers.faces[g] = vec![q, s, o];
            slivers.faces.push(vec![s, p, o]);
        }
    }
    // A zero-area face: three collinear points on a new spike-free flap would be invisible; the
    // common case is a face repeating an edge's midpoint. Split one edge at its midpoint m and
    // write the degenerate face (p, m, q) alongside the two halves.
    {
        let face = slivers.faces[5].clone();
        let (p, q, r) = (face[0], face[1], face[2]);
        let m =
            slivers.point(0.5 * (slivers.positions[p as usize] + slivers.positions[q as usize]));
        slivers.faces[5] = vec![p, m, r];
        slivers.faces.push(vec![m, q, r]);
        if let Some(g) = (0..slivers.faces.len()).find(|&g| {
            let h = &slivers.faces[g];
            h.len() == 3 && (0..3).any(|k| h[k] == q && h[(k + 1) % 3] == p)
        }) {
            let h = slivers.faces[g].clone();
            let k = (0..3).find(|&k| h[k] == q).unwrap_or(0);
            let o = h[(k + 2) % 3];
            slivers.faces[g] = vec![q, m, o];
            slivers.faces.push(vec![m, p, o]);
        }
        slivers.faces.push(vec![p, q, m]);
    }
    files.push((
        "sliver-sphere.obj",
        "An icosphere with edges split 2 % from one end (sliver triangles) and one zero-area face"
            .into(),
        slivers,
    ));

    // Holes: a jittered icosphere with three patches of faces missing.
    let mut holes = icosphere(2).map(|p| p * (1.0 + 0.02 * jitter((p.x * 1e6) as i64 as u64, 4)));
    let centres = [DVec3::X, DVec3::new(-0.5, 0.7, 0.5), -DVec3::Z];
    let positions = holes.positions.clone();
    holes.faces.retain(|f| {
        let c = f.iter().map(|&i| positions[i as usize]).sum::<DVec3>() / 3.0;
        centres.iter().all(|h| c.normalize().dot(*h) < 0.93)
    });
    files.push((
        "holed-sphere.obj",
        "A jittered icosphere with three holes".into(),
        holes,
    ));

    // One flipped face: the octahedron with face 0 written the wrong way round.
    let mut octahedron = Polygons::new();
    for p in [
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ] {
        octahedron.point(p);
    }
    // (0, 2, 4) faces outward; it is written (0, 4, 2).
    let faces: [[u32; 3]; 8] = [
        [0, 4, 2],
        [0, 5, 2],
        [0, 4, 3],
        [0, 3, 5],
        [1, 4, 2],
        [1, 2, 5],
        [1, 3, 4],
        [1, 5, 3],
    ];
    octahedron.faces.extend(faces.iter().map(|f| f.to_vec()));
    files.push((
        "octahedron-flipped.obj",
        "The regular octahedron with its first face written the wrong way round".into(),
        octahedron,
    ));

    files.push((
        "far-blob.obj",
        "A closed quad blob of radius 1 centred at (1e8, -2e8, 3e8)".into(),
        quad_sphere(6, 1.0, 0.04, 5).map(|p| p + DVec3::new(1e8, -2e8, 3e8)),
    ));

    // A CAD part: a U-shaped bracket of planar quads, every crease 90°.
    files.push((
        "u-bracket.obj",
        "A U-shaped bracket: planar faces (quads), every crease 90°; use --crease-angle 40".into(),
        voxels([6, 2, 4], 0.25, |x, _, z| z == 0 || x == 0 || x == 5),
    ));

    // An assembly of open parts that touch, like a teapot's: body, lid, spout and handle.
    let mut pot = revolution(24, 8, |t| {
        let z = 1.2 * t;
        (
            if t == 0.0 {
                0.0
            } else {
                1.0 + 0.35 * (PI * t).sin() - 0.2 * t
            },
            z,
        )
    });
    // The lid rests on the body's rim (radius 0.8 at z = 1.2): its rim is 1e-4 above.
    pot.append(revolution(24, 4, |t| {
        (
            if t == 0.0 { 0.0 } else { 0.82 * t },
            1.2001 + 0.25 * (1.0 - t * t),
        )
    }));
    // The spout starts inside the body's wall and leaves it upwards; open at both ends.
    pot.append(tube(
        12,
        6,
        |t| DVec3::new(1.0 + 0.9 * t, 0.0, 0.35 + 0.9 * t * t),
        |t| 0.18 - 0.08 * t,
        |t| {
            let along = DVec3::new(0.9, 0.0, 1.8 * t).normalize();
            (DVec3::Y, along.cross(DVec3::Y))
        },
    ));
    // The handle: half a torus from the body's wall to the body's wall.
    pot.append(tube(
        10,
        10,
        |t| {
            let a = PI * (0.15 + 0.7 * t);
            DVec3::new(-1.05 - 0.55 * a.sin(), 0.0, 0.6 - 0.5 * a.cos())
        },
        |_| 0.08,
        |t| {
            let a = PI * (0.15 + 0.7 * t);
            let along = DVec3::new(-a.cos(), 0.0, a.sin());
            (DVec3::Y, along.cross(DVec3::Y))
        },
    ));
    files.push((
        "teapot-parts.obj",
        "An assembly of four open parts that touch: body (open at the top), lid, spout, handle"
            .into(),
        pot,
    ));

    // A stray vertex, as a corrupted file has: the icosahedron with its first vertex moved
    // 1e6 away, so that its five faces are needles.
    let (mut positions, faces) = smoothlab::mesh::generate::icosahedron();
    positions[0] = DVec3::new(1e6, 0.0, 0.0);
    files.push((
        "stray-vertex.obj",
        "The regular icosahedron with its first vertex moved to (1e6, 0, 0): a stray vertex \
         whose five faces are needles"
            .into(),
        Polygons {
            positions,
            faces: faces.iter().map(|f| f.to_vec()).collect(),
        },
    ));

    files.push((
        "uv-sphere.obj",
        "A UV sphere of 64 meridians and 32 bands: planar quads, and poles of valence 64".into(),
        uv_sphere(64, 32),
    ));

    for (name, header, mesh) in &files {
        let text = mesh.obj(header);
        std::fs::write(dir.join(name), &text)?;
        println!("{name}: {} bytes", text.len());
    }
    Ok(())
}
