//! Mesh input formats end to end: the scanned bunny written as PLY (ASCII, binary of both byte
//! orders), OFF and STL (ASCII, binary) loads as the same mesh as its OBJ and gives the same
//! `metrics` output; malformed files of every format are clear errors, never panics, also
//! when mutated at random.

mod common;

use std::path::{Path, PathBuf};

use common::mesh_files::{self, Endian};
use common::{scratch, smoothlab};
use glam::DVec3;
use smoothlab::Error;
use smoothlab::mesh::{LoadOptions, LoadReport, Mesh, MeshFormat};

fn bunny() -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny.obj");
    Mesh::load(&path).expect("the bunny loads").0
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write mesh file");
    path
}

fn parse(bytes: &[u8], format: MeshFormat) -> smoothlab::Result<(Mesh, LoadReport)> {
    Mesh::parse_format(bytes, format, &LoadOptions::default())
}

/// The message of a [`Error::MalformedMesh`] of `format`; panics on anything else.
fn malformed(bytes: &[u8], format: MeshFormat) -> String {
    match parse(bytes, format) {
        Err(Error::MalformedMesh {
            format: name,
            message,
            ..
        }) if name == format.name() => message,
        other => panic!("expected a malformed {}, got {other:?}", format.name()),
    }
}

/// True if both meshes have the same faces over the same positions, whatever the vertex
/// numbering (STL has none of its own).
fn same_geometry(a: &Mesh, b: &Mesh) -> bool {
    a.vertex_count() == b.vertex_count()
        && a.face_count() == b.face_count()
        && a.faces().iter().zip(b.faces()).all(|(fa, fb)| {
            (0..3).all(|c| {
                a.positions()[fa[c] as usize].to_array() == b.positions()[fb[c] as usize].to_array()
            })
        })
}

/// The bunny in every format with its file name; the STL files hold the f32-rounded bunny.
fn bunny_files(mesh: &Mesh) -> Vec<(&'static str, Vec<u8>)> {
    let (positions, faces) = (mesh.positions(), mesh.faces());
    let polygons = mesh_files::polygons(faces);
    vec![
        (
            "bunny-ascii.ply",
            mesh_files::ply_ascii(positions, &polygons),
        ),
        (
            "bunny-le.ply",
            mesh_files::ply_binary(positions, &polygons, Endian::Little),
        ),
        (
            "bunny-be.PLY",
            mesh_files::ply_binary(positions, &polygons, Endian::Big),
        ),
        ("bunny.off", mesh_files::off(positions, &polygons)),
        ("bunny-ascii.stl", mesh_files::stl_ascii(positions, faces)),
        (
            "bunny-binary.Stl",
            mesh_files::stl_binary(positions, faces, "solid bunny, binary"),
        ),
    ]
}

#[test]
fn the_bunny_loads_as_the_same_mesh_from_every_format() {
    let obj = bunny();
    let rounded = Mesh::from_triangles(
        mesh_files::rounded_to_f32(obj.positions()),
        obj.faces().to_vec(),
    )
    .expect("the rounded bunny is valid")
    .0;
    assert_ne!(rounded.positions(), obj.positions(), "the bunny is not f32");
    let dir = scratch("mesh_formats", "bunny-mesh");
    for (name, bytes) in bunny_files(&obj) {
        let (mesh, report) = Mesh::load(&write(&dir, name, &bytes)).expect(name);
        if name.to_lowercase().ends_with(".stl") {
            // Every vertex but the first copy of each position is welded, all exactly.
            assert_eq!(report.welded, 3 * obj.face_count() - obj.vertex_count());
            assert_eq!(report.welded_near, 0);
            assert!(same_geometry(&mesh, &rounded), "{name}");
        } else {
            assert_eq!(mesh.positions(), obj.positions(), "{name}");
            assert_eq!(mesh.faces(), obj.faces(), "{name}");
            assert_eq!(report, LoadReport::default(), "{name}");
        }
        assert!(report.warnings.is_empty(), "{name}: {:?}", report.warnings);
    }
}

/// The `metrics --json` output of `mesh` with `pn`, without the timing.
fn metrics_json(mesh: &Path, dir: &Path) -> serde_json::Value {
    let json = dir.join(format!(
        "{}.json",
        mesh.file_name().unwrap().to_string_lossy()
    ));
    let out = smoothlab(&[
        "metrics",
        mesh.to_str().expect("utf-8 path"),
        "--scheme",
        "pn",
        "--json",
        json.to_str().expect("utf-8 path"),
    ]);
    assert!(
        out.status.success(),
        "{}: {}",
        mesh.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let mut value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("JSON written")).unwrap();
    for entry in value.as_array_mut().expect("one entry per scheme") {
        entry
            .as_object_mut()
            .expect("an object")
            .remove("construct_ms")
            .expect("a timing field");
    }
    value
}

#[test]
fn the_bunny_gives_identical_metrics_from_every_format() {
    let obj = bunny();
    let dir = scratch("mesh_formats", "bunny-metrics");
    let from_obj = metrics_json(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny.obj"),
        &dir,
    );
    // STL can only hold the f32-rounded bunny, and has no vertex numbering: its vertices come
    // in order of first use, which changes the order of some sums. Its reference is the
    // rounded bunny as OBJ, vertices renumbered in order of first use.
    let mut number = vec![u32::MAX; obj.vertex_count()];
    let mut positions = Vec::new();
    for &v in obj.faces().iter().flatten() {
        if number[v as usize] == u32::MAX {
            number[v as usize] = positions.len() as u32;
            positions.push(obj.positions()[v as usize]);
        }
    }
    let faces = obj
        .faces()
        .iter()
        .map(|f| f.map(|v| number[v as usize]))
        .collect();
    let rounded = Mesh::from_triangles(mesh_files::rounded_to_f32(&positions), faces)
        .unwrap()
        .0;
    let from_rounded_obj = metrics_json(
        &write(&dir, "bunny-f32.obj", rounded.to_obj("").as_bytes()),
        &dir,
    );
    assert_ne!(from_obj, from_rounded_obj, "rounding changes nothing?");
    for (name, bytes) in bunny_files(&obj) {
        let metrics = metrics_json(&write(&dir, name, &bytes), &dir);
        let expected = if name.to_lowercase().ends_with(".stl") {
            &from_rounded_obj
        } else {
            &from_obj
        };
        assert_eq!(&metrics, expected, "{name}");
    }
}

/// A unit cube of six quads (outward), vertex `i` at the bits of `i`.
fn cube() -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let positions = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64))
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    (positions, quads.iter().map(|q| q.to_vec()).collect())
}

/// The cube's quads as triangles, for STL.
fn cube_triangles() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let (positions, quads) = cube();
    let faces = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (positions, faces)
}

#[test]
fn ply_quads_are_triangulated_with_a_warning_and_bent_ones_repaired() {
    let (mut positions, quads) = cube();
    for bytes in [
        mesh_files::ply_ascii(&positions, &quads),
        mesh_files::ply_binary(&positions, &quads, Endian::Big),
    ] {
        let (mesh, report) = parse(&bytes, MeshFormat::Ply).unwrap();
        assert_eq!(mesh.face_count(), 12);
        assert!(mesh.is_closed());
        assert!(report.warnings[0].starts_with("triangulated 6 faces with more than 3 corners"));
    }
    positions[7].z = 1.1;
    let bytes = mesh_files::ply_ascii(&positions, &quads);
    let (_, report) = parse(&bytes, MeshFormat::Ply).unwrap();
    assert_eq!(report.repairs[0].first, smoothlab::mesh::Element::Face(1));
    let strict = LoadOptions {
        strict: true,
        ..Default::default()
    };
    let err = Mesh::parse_format(&bytes, MeshFormat::Ply, &strict).unwrap_err();
    assert!(matches!(err, Error::RepairRefused { .. }), "{err:?}");
    assert!(
        err.to_string()
            .starts_with("face 1: it has 4 corners and is not planar")
    );
}

#[test]
fn malformed_ply_files_are_clear_errors() {
    let (positions, quads) = cube();
    let ascii = String::from_utf8(mesh_files::ply_ascii(&positions, &quads)).unwrap();
    let ply = MeshFormat::Ply;
    assert!(malformed(b"", ply).starts_with("bad header"));
    assert!(malformed(b"PLY file\n", ply).starts_with("bad header"));
    assert!(
        malformed(ascii.replace("ascii", "utf16").as_bytes(), ply).starts_with("bad header"),
        "unknown encoding"
    );
    assert!(malformed(ascii.replace("end_header\n", "").as_bytes(), ply).starts_with("bad header"));
    assert_eq!(
        malformed(ascii.replace("property double y\n", "").as_bytes(), ply),
        "bad header: the 'vertex' element has no 'y' property"
    );
    let points = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nend_header\n0 0 0\n";
    assert!(malformed(points.as_bytes(), ply).contains("no 'face' element"));
    let float_indices = ascii.replace(
        "list uchar int vertex_indices",
        "list uchar float vertex_indices",
    );
    assert!(malformed(float_indices.as_bytes(), ply).contains("not a list of integers"));
    // Short ASCII data, unreadable numbers, negative indices.
    let short: String = ascii.lines().take(14).map(|l| format!("{l}\n")).collect();
    assert!(malformed(short.as_bytes(), ply).contains("vertex"));
    assert!(
        malformed(ascii.replace("\n1 1 0 1\n", "\n1 x 0 1\n").as_bytes(), ply).contains("vertex")
    );
    assert_eq!(
        malformed(ascii.replace("4 0 1 5 4", "4 0 1 5 -4").as_bytes(), ply),
        "face 2 refers to vertex -4"
    );
    // Typed errors from the shared checks.
    assert!(matches!(
        parse(ascii.replace("4 0 1 5 4", "4 0 1 5 8").as_bytes(), ply).unwrap_err(),
        Error::VertexIndexOutOfRange {
            face: 2,
            vertex: 8,
            count: 8
        }
    ));
    // A NaN coordinate is the same typed error in ASCII as in binary.
    assert!(matches!(
        parse(
            ascii.replace("\n1 1 0 1\n", "\n1 nan 0 1\n").as_bytes(),
            ply
        )
        .unwrap_err(),
        Error::NonFiniteVertex { vertex: 3 }
    ));
    let mut nan = positions.clone();
    nan[6].x = f64::NAN;
    assert!(matches!(
        parse(&mesh_files::ply_binary(&nan, &quads, Endian::Little), ply).unwrap_err(),
        Error::NonFiniteVertex { vertex: 6 }
    ));
}

#[test]
fn every_truncated_binary_ply_is_an_error_not_a_panic() {
    let (positions, quads) = cube();
    for endian in [Endian::Little, Endian::Big] {
        let bytes = mesh_files::ply_binary(&positions, &quads, endian);
        assert!(parse(&bytes, MeshFormat::Ply).is_ok());
        for end in 0..bytes.len() {
            let err = parse(&bytes[..end], MeshFormat::Ply).unwrap_err();
            assert!(
                matches!(err, Error::MalformedMesh { .. }),
                "{endian:?}, {end} bytes: {err:?}"
            );
        }
        // A list length of 2^31 in a short file is an error, not an allocation.
        let mut huge = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
            property float x\nproperty float y\nproperty float z\nelement face 1\n\
            property list uint int vertex_indices\nend_header\n"
            .to_vec();
        huge.extend([0u8; 36]);
        huge.extend(0x8000_0000u32.to_le_bytes());
        huge.extend([0u8; 12]);
        assert!(malformed(&huge, MeshFormat::Ply).starts_with("element 'face'"));
        // The last face cut short names the element and the end of the file.
        let message = malformed(&bytes[..bytes.len() - 2], MeshFormat::Ply);
        assert!(message.contains("element 'face'"), "{message}");
    }
}

#[test]
fn stl_facets_are_welded_into_a_closed_mesh() {
    let (positions, faces) = cube_triangles();
    for bytes in [
        mesh_files::stl_ascii(&positions, &faces),
        mesh_files::stl_binary(&positions, &faces, ""),
        // Many binary files start their header with the ASCII keyword.
        mesh_files::stl_binary(&positions, &faces, "solid cube"),
        // An ASCII solid without a name.
        String::from_utf8(mesh_files::stl_ascii(&positions, &faces))
            .unwrap()
            .replacen("solid test", "solid", 1)
            .into_bytes(),
    ] {
        let (mesh, report) = parse(&bytes, MeshFormat::Stl).unwrap();
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (8, 12));
        assert!(mesh.is_closed());
        assert_eq!((report.welded, report.welded_near), (28, 0));
        assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    }
}

#[test]
fn malformed_stl_files_are_clear_errors() {
    let (positions, faces) = cube_triangles();
    let stl = MeshFormat::Stl;
    let binary = mesh_files::stl_binary(&positions, &faces, "cube");
    for end in 0..binary.len() {
        let err = parse(&binary[..end], stl).unwrap_err();
        assert!(
            matches!(err, Error::MalformedMesh { .. }),
            "{end} bytes: {err:?}"
        );
    }
    assert_eq!(
        malformed(&binary[..binary.len() - 1], stl),
        "not ASCII (no 'solid' keyword), and as binary the header announces 12 facets (684 \
         bytes) but the file has 683 bytes: truncated, padded or not STL"
    );
    // A padded binary file whose header starts with `solid` gets the same size message.
    let mut padded = mesh_files::stl_binary(&positions, &faces, "solid cube");
    padded.extend([0u8; 7]);
    assert_eq!(
        malformed(&padded, stl),
        "not ASCII (it starts with 'solid' but holds binary data), and as binary the header \
         announces 12 facets (684 bytes) but the file has 691 bytes: truncated, padded or not STL"
    );
    assert!(parse(&padded[..684], stl).is_ok());
    assert!(malformed(b"cube", stl).contains("shorter than the 84-byte binary header"));
    let ascii = String::from_utf8(mesh_files::stl_ascii(&positions, &faces)).unwrap();
    let missing_endloop = ascii.replacen("    endloop\n", "", 1);
    assert!(
        malformed(missing_endloop.as_bytes(), stl).starts_with("facet 0: expected [\"endloop\"]")
    );
    let truncated = &ascii[..ascii.len() / 2];
    assert!(malformed(truncated.as_bytes(), stl).contains("EOF"));
    let nan_ascii = ascii.replacen("vertex 0 0 0", "vertex 0 nan 0", 1);
    assert!(malformed(nan_ascii.as_bytes(), stl).contains("finite"));
    // Binary NaN: vertex 3·facet + corner.
    let mut nan = positions.clone();
    nan[3].y = f64::NAN;
    let first_use = faces
        .iter()
        .flatten()
        .position(|&v| v == 3)
        .expect("vertex 3 is used");
    assert!(matches!(
        parse(&mesh_files::stl_binary(&nan, &faces, ""), stl).unwrap_err(),
        Error::NonFiniteVertex { vertex } if vertex == first_use
    ));
}

#[test]
fn the_command_line_reads_every_format_and_names_unknown_extensions() {
    let dir = scratch("mesh_formats", "cli");
    let (positions, quads) = cube();
    let off = write(&dir, "cube.OFF", &mesh_files::off(&positions, &quads));
    let out = smoothlab(&["metrics", off.to_str().unwrap(), "--scheme", "flat"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: triangulated 6 faces with more than 3 corners"),
        "{stderr}"
    );
    let unknown = write(&dir, "cube.gltf", b"{}");
    let out = smoothlab(&["metrics", unknown.to_str().unwrap(), "--scheme", "flat"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "cube.gltf: unknown mesh format '.gltf'; supported extensions: .obj, \
             .ply, .off, .stl"
        ),
        "{stderr}"
    );
    let bytes = mesh_files::ply_binary(&positions, &quads, Endian::Little);
    let truncated = write(&dir, "cut.ply", &bytes[..bytes.len() - 3]);
    let out = smoothlab(&["metrics", truncated.to_str().unwrap(), "--scheme", "flat"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("cut.ply: malformed PLY: element 'face'"),
        "{stderr}"
    );
}

/// Files of every format mutated at random (seeded: the same cases on every run) — bytes
/// changed, cut, repeated or replaced by numbers and words the formats use (`nan`, `1e308`,
/// counts of 2^32, `end_header`, …) — either load, with their repairs, or are errors; a
/// loaded mesh then builds or is refused by `pn` and `hb`. None panics. (The same mutations,
/// 100,000 of them through the command line, found no panic either.)
#[test]
fn mutated_files_of_every_format_load_or_fail_cleanly() {
    let (positions, quads) = cube();
    let (_, triangles) = cube_triangles();
    let blob = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/icosahedron.obj"))
        .expect("read the icosahedron");
    let seeds: [(MeshFormat, Vec<u8>); 6] = [
        (MeshFormat::Obj, blob),
        (MeshFormat::Ply, mesh_files::ply_ascii(&positions, &quads)),
        (
            MeshFormat::Ply,
            mesh_files::ply_binary(&positions, &quads, Endian::Little),
        ),
        (MeshFormat::Off, mesh_files::off(&positions, &quads)),
        (
            MeshFormat::Stl,
            mesh_files::stl_ascii(&positions, &triangles),
        ),
        (
            MeshFormat::Stl,
            mesh_files::stl_binary(&positions, &triangles, "cube"),
        ),
    ];
    let words: [&[u8]; 14] = [
        b"0",
        b"-1",
        b"nan",
        b"inf",
        b"1e308",
        b"4294967296",
        b"255",
        b"\n",
        b" ",
        b"\0",
        b"end_header",
        b"facet",
        b"v 1 2",
        b"f 1 1 2",
    ];
    let mut rng = smoothlab::testing::Rng::new(20_261_207);
    let mut below = |n: usize| (rng.next_u64() % n.max(1) as u64) as usize;
    let (mut loaded, mut refused, mut built) = (0, 0, 0);
    for case in 0..1200 {
        let (format, seed) = &seeds[case % seeds.len()];
        let mut bytes = seed.clone();
        for _ in 0..1 + below(2) * below(4) {
            let at = below(bytes.len());
            match below(4) {
                0 => bytes[at] = below(256) as u8,
                1 => {
                    let end = (at + 1 + below(16)).min(bytes.len());
                    bytes.drain(at..end);
                }
                2 => {
                    let word = words[below(words.len())];
                    bytes.splice(at..at, word.iter().copied());
                }
                _ => {
                    let from = below(bytes.len());
                    let end = (from + 1 + below(48)).min(bytes.len());
                    let copied: Vec<u8> = bytes[from..end].to_vec();
                    bytes.splice(at..at, copied);
                }
            }
            if bytes.is_empty() {
                break;
            }
        }
        let outcome = std::panic::catch_unwind(|| {
            let Ok((mesh, _)) = parse(&bytes, *format) else {
                return (false, 0);
            };
            let schemes = ["pn", "hb"]
                .iter()
                .filter(|s| smoothlab::schemes::build(s, &mesh, &[]).is_ok())
                .count();
            (true, schemes)
        });
        let Ok((ok, schemes)) = outcome else {
            panic!(
                "case {case} ({}) panicked on:\n{}",
                format.name(),
                String::from_utf8_lossy(&bytes)
            );
        };
        if ok {
            loaded += 1;
            built += schemes;
        } else {
            refused += 1;
        }
    }
    // The mutations reach both outcomes, and the schemes' own checks behind loading.
    assert!(
        loaded > 100 && refused > 100,
        "{loaded} loaded, {refused} refused"
    );
    assert!(
        built > 100,
        "{built} surfaces built from {loaded} loaded meshes"
    );
}
