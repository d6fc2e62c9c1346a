//! Wavefront OBJ input (through tobj) and output.
//!
//! smoothlab reads only geometry: `v`, `vn` and `f` records. Object, group and material
//! statements are dropped before tobj sees the text, so all objects of a file form one model
//! (one mesh); polyline (`l`) records are dropped with a warning; texture coordinates (`vt`)
//! are checked and dropped. tobj is run with
//! `single_index = false` so that per-corner normal and texture indices never split a vertex,
//! and with `triangulate = false` so that polygons are reported instead of silently split.
//!
//! A scan of the records before tobj gives what tobj does not expose: errors naming the line
//! and the record (`v`, `vn`, `vt` numbers, face corners, a NaN or infinite coordinate of any
//! vertex, used or not), records continued over lines ending in `\`, the file number of every
//! corner's vertex, range errors naming the face, and which corners have no normal
//! index (tobj fills those with a neighbour's normal, which must not pass as the vertex's
//! normal). With the file numbers the loaded mesh keeps the file's vertex order (tobj's is the
//! order of first use), and errors name vertices by their 0-based file number.

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use super::formats::numbered_lines;
use super::normals::CornerNormals;
use super::polygon::{self, PolygonMesh};
use super::{LoadOptions, LoadReport, Mesh};
use crate::error::{Error, Result};

/// Statements that group or decorate geometry; they do not change the surface.
const DROPPED_STATEMENTS: [&str; 4] = ["o", "g", "usemtl", "mtllib"];

/// What the scan of the raw text found.
struct Scan {
    /// The text handed to tobj: the input without grouping statements and polylines.
    geometry: String,
    /// Number of `v` records.
    vertex_count: usize,
    /// 0-based file number of the vertex at every face corner, in file order.
    corner_vertex: Vec<u32>,
    /// True if the file has `vn` records.
    has_normals: bool,
    /// The first (face, corner, index among all corners) written without a normal index.
    first_corner_without_normal: Option<(usize, usize, usize)>,
    /// Number of `l` records dropped.
    polylines: usize,
    /// What the file says about sharp edges: smoothing groups and per-corner normals.
    sharpness: FileSharpness,
}

/// The records that mark sharp edges in an OBJ file.
#[derive(Default)]
struct FileSharpness {
    /// True if the file has an `s` record.
    has_groups: bool,
    /// The smoothing group of every face (`s off` and `s 0` are group 0, the default).
    face_group: Vec<u64>,
    /// The file's `vn` records.
    normals: Vec<DVec3>,
    /// Per face corner (file order), its 0-based normal index, if it names one.
    corner_normal: Vec<Option<i64>>,
    /// Per face corner, its face.
    corner_face: Vec<usize>,
}

impl FileSharpness {
    /// The edges (pairs of 0-based file vertex numbers) the file marks sharp: those whose two
    /// faces are in different smoothing groups, or give one of its ends normals more than
    /// [`super::OBJ_NORMAL_ANGLE_TOLERANCE`] apart. Edges with more than two faces are left
    /// to validation. `corner_vertex` is the file vertex of every corner.
    fn sharp_edges(&self, corner_vertex: &[u32]) -> Vec<[u32; 2]> {
        let normal = |corner: usize| {
            let index = self.corner_normal[corner]?;
            usize::try_from(index)
                .ok()
                .and_then(|i| self.normals.get(i).copied())
        };
        let differ = |x: Option<DVec3>, y: Option<DVec3>| match (x, y) {
            (Some(x), Some(y)) => {
                super::normals::angle_between(x, y) > super::OBJ_NORMAL_ANGLE_TOLERANCE
            }
            _ => false,
        };
        // (edge key, face, corner at the smaller vertex, corner at the larger one)
        let mut sides: Vec<((u32, u32), usize, usize, usize)> = Vec::new();
        let mut start = 0;
        while start < corner_vertex.len() {
            let face = self.corner_face[start];
            let end = start
                + self.corner_face[start..]
                    .iter()
                    .take_while(|&&f| f == face)
                    .count();
            for i in start..end {
                let j = if i + 1 == end { start } else { i + 1 };
                let (a, b) = (corner_vertex[i], corner_vertex[j]);
                let (lo, hi) = if a <= b { (i, j) } else { (j, i) };
                sides.push(((a.min(b), a.max(b)), face, lo, hi));
            }
            start = end;
        }
        sides.sort_unstable_by_key(|side| (side.0, side.1));
        sides
            .chunk_by(|x, y| x.0 == y.0)
            .filter(|pair| pair.len() == 2)
            .filter(|pair| {
                let (x, y) = (pair[0], pair[1]);
                let groups = self.has_groups && self.face_group[x.1] != self.face_group[y.1];
                groups || differ(normal(x.2), normal(y.2)) || differ(normal(x.3), normal(y.3))
            })
            .map(|pair| [pair[0].0.0, pair[0].0.1])
            .collect()
    }
}

fn malformed(origin: &Path, message: String) -> Error {
    Error::MalformedObj {
        path: origin.to_path_buf(),
        message,
    }
}

/// The records of OBJ text: 1-based number of the first line and the record's text. A line
/// ending in `\` continues on the next line, as the OBJ specification allows.
fn records(text: &str) -> impl Iterator<Item = (usize, std::borrow::Cow<'_, str>)> {
    let mut lines = numbered_lines(text);
    std::iter::from_fn(move || {
        let (number, first) = lines.next()?;
        let Some(head) = first.trim_end().strip_suffix('\\') else {
            return Some((number, first.into()));
        };
        let mut joined = head.to_string();
        for (_, next) in lines.by_ref() {
            joined.push(' ');
            match next.trim_end().strip_suffix('\\') {
                Some(head) => joined.push_str(head),
                None => {
                    joined.push_str(next);
                    break;
                }
            }
        }
        Some((number, joined.into()))
    })
}

/// The numbers of a `v`, `vn` or `vt` record (the words after the keyword); `what` names the
/// record in messages, e.g. `line 3: vertex 2`.
fn record_numbers(words: &[&str], what: &str) -> std::result::Result<Vec<f64>, String> {
    words
        .iter()
        .map(|word| {
            word.parse::<f64>().map_err(|_| {
                let hint = if word.contains(',') {
                    " (OBJ numbers use a decimal point and are separated by spaces)"
                } else {
                    ""
                };
                format!("{what}: cannot read the number '{word}'{hint}")
            })
        })
        .collect()
}

/// The position of a `v` record: `x y z`, `x y z w` (divided by w) or `x y z r g b`.
fn vertex_position(words: &[&str], what: &str) -> std::result::Result<DVec3, String> {
    let numbers = record_numbers(words, what)?;
    let xyz = match numbers.len() {
        3 | 6 => DVec3::from_slice(&numbers),
        4 if numbers[3] == 0.0 => return Err(format!("{what} has the weight w = 0")),
        4 => DVec3::from_slice(&numbers) / numbers[3],
        n => {
            return Err(format!(
                "{what} has {n} numbers; expected x y z, x y z w or x y z r g b"
            ));
        }
    };
    Ok(xyz)
}

fn scan(text: &str, origin: &Path) -> Result<Scan> {
    let mut scan = Scan {
        geometry: String::with_capacity(text.len()),
        vertex_count: 0,
        corner_vertex: Vec::new(),
        has_normals: false,
        first_corner_without_normal: None,
        polylines: 0,
        sharpness: FileSharpness::default(),
    };
    let mut group = 0u64;
    // Resolved (line, face, 0-based index) per corner, of its vertex, normal and texture
    // coordinate; checked once all records are counted because tobj, like many writers,
    // accepts forward references. tobj checks normals only when the file has normals at all,
    // and is given no texture coordinates (smoothlab reads none).
    let mut corners: Vec<(usize, usize, i64)> = Vec::new();
    let mut corner_normals: Vec<(usize, usize, i64)> = Vec::new();
    let mut corner_texcoords: Vec<(usize, usize, i64)> = Vec::new();
    let (mut normal_count, mut texcoord_count) = (0, 0);
    let mut face = 0;
    for (line, record) in records(text) {
        let bad = |message: String| malformed(origin, format!("line {line}: {message}"));
        let words: Vec<&str> = record.split_whitespace().collect();
        let keyword = words.first().copied().unwrap_or("");
        if DROPPED_STATEMENTS.contains(&keyword) {
            continue;
        }
        match keyword {
            "l" => {
                scan.polylines += 1;
                continue;
            }
            "v" => {
                let vertex = scan.vertex_count;
                let position =
                    vertex_position(&words[1..], &format!("vertex {vertex}")).map_err(bad)?;
                if !position.is_finite() {
                    return Err(Error::NonFiniteVertex { vertex });
                }
                scan.vertex_count += 1;
            }
            "vn" => {
                let what = format!("normal {normal_count}");
                let numbers = record_numbers(&words[1..], &what).map_err(bad)?;
                if numbers.len() != 3 {
                    return Err(bad(format!(
                        "{what} has {} numbers, expected 3",
                        numbers.len()
                    )));
                }
                normal_count += 1;
                scan.sharpness.normals.push(DVec3::from_slice(&numbers));
            }
            "s" => {
                group = match words.get(1).copied() {
                    Some("off") | None => 0,
                    Some(word) => word.parse().map_err(|_| {
                        bad(format!(
                            "smoothing group '{word}' is neither a number nor 'off'"
                        ))
                    })?,
                };
                scan.sharpness.has_groups = true;
            }
            "vt" => {
                let what = format!("texture coordinate {texcoord_count}");
                let numbers = record_numbers(&words[1..], &what).map_err(bad)?;
                if !(1..=3).contains(&numbers.len()) {
                    return Err(bad(format!(
                        "{what} has {} numbers, expected 1 to 3 (u [v [w]])",
                        numbers.len()
                    )));
                }
                texcoord_count += 1;
                continue;
            }
            "f" => {
                for (corner, word) in words[1..].iter().enumerate() {
                    let fields: Vec<&str> = word.split('/').collect();
                    if fields.len() > 3 {
                        return Err(bad(format!(
                            "face {face}: corner '{word}' has more than vertex/texture/normal"
                        )));
                    }
                    let index = |field: &str, what: &str, count: usize| {
                        let index: i64 = field.parse().map_err(|_| {
                            bad(format!("face {face}: cannot read the {what} in '{word}'"))
                        })?;
                        resolve_index(index, count).ok_or_else(|| {
                            bad(format!(
                                "face {face}: {what} index 0 in '{word}' (OBJ indices start at 1)"
                            ))
                        })
                    };
                    corners.push((line, face, index(fields[0], "vertex", scan.vertex_count)?));
                    if let Some(texcoord) = fields.get(1).filter(|t| !t.is_empty()) {
                        let resolved = index(texcoord, "texture coordinate", texcoord_count)?;
                        corner_texcoords.push((line, face, resolved));
                    }
                    scan.sharpness.corner_face.push(face);
                    match fields.get(2).filter(|n| !n.is_empty()) {
                        Some(normal) => {
                            let resolved = index(normal, "normal", normal_count)?;
                            corner_normals.push((line, face, resolved));
                            scan.sharpness.corner_normal.push(Some(resolved));
                        }
                        None => {
                            scan.sharpness.corner_normal.push(None);
                            if scan.first_corner_without_normal.is_none() {
                                scan.first_corner_without_normal =
                                    Some((face, corner, corners.len() - 1));
                            }
                        }
                    }
                }
                scan.sharpness.face_group.push(group);
                face += 1;
            }
            _ => {}
        }
        scan.geometry.push_str(&record);
        scan.geometry.push('\n');
    }
    for &(line, face, vertex) in &corners {
        if vertex < 0 {
            return Err(malformed(
                origin,
                format!("line {line}: face {face} refers to a vertex before the first one"),
            ));
        }
        if vertex >= scan.vertex_count as i64 {
            return Err(Error::VertexIndexOutOfRange {
                face,
                vertex: vertex as usize,
                count: scan.vertex_count,
            });
        }
    }
    for (records, count, what) in [
        (&corner_normals, normal_count, "normal"),
        (&corner_texcoords, texcoord_count, "texture coordinate"),
    ] {
        if let Some(&(line, face, index)) = records
            .iter()
            .find(|&&(_, _, i)| !(0..count as i64).contains(&i))
        {
            return Err(malformed(
                origin,
                format!(
                    "line {line}: face {face} refers to {what} {index} (0-based), but the file \
                     has {count}"
                ),
            ));
        }
    }
    scan.has_normals = normal_count > 0;
    scan.corner_vertex = corners.iter().map(|&(_, _, v)| v as u32).collect();
    Ok(scan)
}

/// The 0-based index of an OBJ index (1-based, or negative counting back from the last of
/// the `count` records read so far); None for the invalid index 0. May be out of range.
fn resolve_index(index: i64, count: usize) -> Option<i64> {
    match index {
        0 => None,
        i if i < 0 => Some(count as i64 + i),
        i => Some(i - 1),
    }
}

/// Parses OBJ text; `origin` names the file in errors. A leading UTF-8 byte-order mark is
/// skipped.
pub(super) fn parse(
    text: &str,
    origin: &Path,
    options: &LoadOptions,
) -> Result<(Mesh, LoadReport)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let scan = scan(text, origin)?;
    let tobj_options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: false,
        ignore_lines: false,
    };
    // Materials were dropped with their statements, so the loader is never asked for one.
    let (models, _materials) =
        tobj::load_obj_buf(&mut scan.geometry.as_bytes(), &tobj_options, |_| {
            Ok(Default::default())
        })
        .map_err(|e| malformed(origin, e.to_string()))?;

    let mut positions: Vec<DVec3> = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    let mut arities: Vec<u32> = Vec::new();
    let mut normals: Vec<DVec3> = Vec::new();
    let mut normal_corners: Vec<u32> = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let (position_base, normal_base) = (positions.len() as u32, normals.len() as u32);
        positions.extend(mesh.positions.chunks_exact(3).map(DVec3::from_slice));
        normals.extend(mesh.normals.chunks_exact(3).map(DVec3::from_slice));
        corners.extend(mesh.indices.iter().map(|&i| i + position_base));
        normal_corners.extend(mesh.normal_indices.iter().map(|&i| i + normal_base));
        if mesh.face_arities.is_empty() {
            arities.extend(std::iter::repeat_n(3, mesh.indices.len() / 3));
        } else {
            arities.extend(&mesh.face_arities);
        }
    }
    if corners.len() != scan.corner_vertex.len() {
        return Err(malformed(
            origin,
            format!(
                "{} face corners parsed, {} expected from the face records",
                corners.len(),
                scan.corner_vertex.len()
            ),
        ));
    }
    // tobj numbers vertices in order of first use; put them back in file order, so that the
    // mesh numbers its vertices as the file does (less unused and welded ones).
    let mut file_number = vec![u32::MAX; positions.len()];
    for (&local, &file) in corners.iter().zip(&scan.corner_vertex) {
        file_number[local as usize] = file;
    }
    let mut file_order: Vec<u32> = (0..positions.len() as u32).collect();
    file_order.sort_unstable_by_key(|&local| file_number[local as usize]);
    let mut rank = vec![0u32; positions.len()];
    for (r, &local) in file_order.iter().enumerate() {
        rank[local as usize] = r as u32;
    }
    let positions: Vec<DVec3> = file_order.iter().map(|&l| positions[l as usize]).collect();
    let labels: Vec<u32> = file_order
        .iter()
        .map(|&l| file_number[l as usize])
        .collect();
    for corner in &mut corners {
        *corner = rank[*corner as usize];
    }
    let corner_normals = if !scan.has_normals {
        Err("the OBJ file has no normals".to_string())
    } else if let Some((face, corner, index)) = scan.first_corner_without_normal {
        let vertex = scan.corner_vertex[index];
        Err(format!(
            "corner {corner} of face {face} (vertex {vertex}) has no normal index"
        ))
    } else if normal_corners.len() != corners.len() {
        Err("some face corners have no normal".to_string())
    } else {
        Ok(CornerNormals {
            normals,
            corner: normal_corners,
        })
    };
    let used_in_file = positions.len();
    // The file's sharp edges, renumbered from file vertices to positions.
    let mut position_of = vec![u32::MAX; scan.vertex_count];
    for (i, &file) in labels.iter().enumerate() {
        position_of[file as usize] = i as u32;
    }
    let file_sharp: Vec<[u32; 2]> = scan
        .sharpness
        .sharp_edges(&scan.corner_vertex)
        .into_iter()
        .map(|pair| pair.map(|v| position_of[v as usize]))
        .collect();
    let polygons = PolygonMesh {
        positions,
        corners,
        arities,
    };
    let (mesh, mut report) = polygon::assemble(
        polygons,
        Some(&labels),
        corner_normals,
        &file_sharp,
        options,
    )?;
    let unused = scan.vertex_count.saturating_sub(used_in_file);
    if unused > 0 {
        report
            .warnings
            .push(format!("dropped {unused} vertices used by no face"));
    }
    if scan.polylines > 0 {
        report
            .warnings
            .push(format!("ignored {} polyline (l) records", scan.polylines));
    }
    Ok((mesh, report))
}

/// OBJ text of a triangle mesh: `header` lines as comments, then `v` and 1-based `f` records.
pub(super) fn write(header: &str, positions: &[DVec3], faces: &[[u32; 3]]) -> String {
    let mut text = String::new();
    for line in header.lines() {
        // Writing to a String cannot fail.
        let _ = writeln!(text, "# {line}");
    }
    for p in positions {
        let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
    }
    for [a, b, c] in faces {
        let _ = writeln!(text, "f {} {} {}", a + 1, b + 1, c + 1);
    }
    text
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::DVec3;

    use crate::error::Error;
    use crate::mesh::generate;
    use crate::mesh::{Mesh, NormalSource};

    /// The octahedron (vertices ±x, ±y, ±z in `v` order 1..6) with normals and texture
    /// coordinates: every corner has its own `vt` and the normal of its vertex.
    const OCTAHEDRON_WITH_NORMALS_AND_UVS: &str = "\
# octahedron with per-corner texture coordinates
v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
vn 1 0 0
vn -1 0 0
vn 0 2 0
vn 0 -1 0
vn 0 0 1
vn 0 0 -1
vt 0 0
vt 1 0
vt 0 1
vt 1 1
g upper
f 1/1/1 3/2/3 5/3/5
f 3/4/3 2/1/2 5/2/5
f 2/3/2 4/4/4 5/1/5
f 4/2/4 1/3/1 5/4/5
o lower
usemtl steel
f 3/1/3 1/2/1 6/3/6
f 2/4/2 3/1/3 6/2/6
f 4/3/4 2/4/2 6/1/6
f 1/2/1 4/3/4 6/4/6
";

    fn parse_err(text: &str) -> Error {
        Mesh::parse_obj(text).unwrap_err()
    }

    fn parse_strict_err(text: &str) -> Error {
        let options = crate::mesh::LoadOptions {
            strict: true,
            ..Default::default()
        };
        Mesh::parse_obj_with(text, &options).unwrap_err()
    }

    #[test]
    fn normals_and_uvs_do_not_split_vertices_and_groups_are_concatenated() {
        let (mesh, report) = Mesh::parse_obj(OCTAHEDRON_WITH_NORMALS_AND_UVS).unwrap();
        assert_eq!(mesh.vertex_count(), 6);
        assert_eq!(mesh.face_count(), 8);
        assert!(mesh.is_closed());
        assert_eq!(report.welded, 0);
        assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        // Normals come back unit length, one per vertex (the file's (0, 2, 0) included).
        let normals = mesh.vertex_normals(NormalSource::Obj).unwrap();
        for (n, p) in normals.iter().zip(mesh.positions()) {
            assert_eq!(n, p);
        }
    }

    #[test]
    fn file_round_trips_through_to_obj_exactly() {
        let (positions, faces) = generate::deformed_icosahedron();
        let (mesh, _) = Mesh::from_triangles(positions, faces).unwrap();
        let text = mesh.to_obj("deformed icosahedron\nsecond header line");
        assert!(text.starts_with("# deformed icosahedron\n# second header line\nv "));
        let (parsed, report) = Mesh::parse_obj(&text).unwrap();
        assert_eq!(parsed.positions(), mesh.positions());
        assert_eq!(parsed.faces(), mesh.faces());
        assert_eq!(report, Default::default());
    }

    #[test]
    fn missing_file_is_an_io_error_naming_the_path() {
        let path = Path::new("/nonexistent/smoothlab/missing.obj");
        let error = Mesh::load_obj(path).unwrap_err();
        assert!(
            matches!(&error, Error::Io { path: p, .. } if p == path),
            "{error}"
        );
        assert!(error.to_string().contains("missing.obj"), "{error}");
    }

    #[test]
    fn load_obj_reads_a_file() {
        let path = std::env::temp_dir().join(format!("smoothlab-obj-{}.obj", std::process::id()));
        std::fs::write(&path, OCTAHEDRON_WITH_NORMALS_AND_UVS).unwrap();
        let loaded = Mesh::load_obj(&path);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(loaded.unwrap().0.face_count(), 8);
    }

    #[test]
    fn unparsable_records_are_malformed_obj() {
        for text in [
            "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\nf 1 2 3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 three\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//4 2//4 3//4\n",
        ] {
            let error = parse_err(text);
            assert!(
                matches!(error, Error::MalformedObj { .. }),
                "{text}: {error}"
            );
        }
    }

    /// The message of a [`Error::MalformedObj`]; panics on anything else.
    fn malformed_message(text: &str) -> String {
        match parse_err(text) {
            Error::MalformedObj { message, .. } => message,
            other => panic!("expected a malformed OBJ, got {other:?}"),
        }
    }

    #[test]
    fn record_errors_name_the_line_and_the_record() {
        let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        for (text, expected) in [
            (
                "v 0 0 0\nv 1,0 0 0\n",
                "line 2: vertex 1: cannot read the number '1,0' (OBJ numbers use a decimal \
                 point and are separated by spaces)",
            ),
            (
                "v 0 0 0\n# two numbers\nv 1 0\n",
                "line 3: vertex 1 has 2 numbers; expected x y z, x y z w or x y z r g b",
            ),
            ("v 0 0 0 0\n", "line 1: vertex 0 has the weight w = 0"),
            (
                &format!("{triangle}vn 0 0\nf 1//1 2//1 3//1\n"),
                "line 4: normal 0 has 2 numbers, expected 3",
            ),
            (
                &format!("{triangle}vn 0 0 one\n"),
                "line 4: normal 0: cannot read the number 'one'",
            ),
            (
                &format!("{triangle}vt 0 0\nvt 0 0 0 0\n"),
                "line 5: texture coordinate 1 has 4 numbers, expected 1 to 3 (u [v [w]])",
            ),
            (
                &format!("{triangle}vt 0 0\nf 1/1 2/1 3/5\n"),
                "line 5: face 0 refers to texture coordinate 4 (0-based), but the file has 1",
            ),
            (
                &format!("{triangle}f 1 2 3\nf 0 1 2\n"),
                "line 5: face 1: vertex index 0 in '0' (OBJ indices start at 1)",
            ),
            (
                &format!("{triangle}f 1 2 x\n"),
                "line 4: face 0: cannot read the vertex in 'x'",
            ),
            (
                &format!("{triangle}f 1 2 3/1/1/1\n"),
                "line 4: face 0: corner '3/1/1/1' has more than vertex/texture/normal",
            ),
            (
                &format!("{triangle}f -4 1 2\n"),
                "line 4: face 0 refers to a vertex before the first one",
            ),
        ] {
            assert_eq!(malformed_message(text), expected, "{text}");
            // CR LF line ends count one line per pair.
            assert_eq!(malformed_message(&text.replace('\n', "\r\n")), expected);
        }
    }

    #[test]
    fn a_non_finite_vertex_is_an_error_even_when_no_face_uses_it() {
        for coordinate in ["nan", "inf", "-inf", "1e400"] {
            let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nv {coordinate} 0 0\nf 1 2 3\n");
            let error = parse_err(&text);
            assert!(
                matches!(error, Error::NonFiniteVertex { vertex: 3 }),
                "{coordinate}: {error}"
            );
        }
        // A weight small enough to overflow the position.
        let error = parse_err("v 1 0 0 1e-320\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(
            matches!(error, Error::NonFiniteVertex { vertex: 0 }),
            "{error}"
        );
    }

    #[test]
    fn a_backslash_continues_a_record_on_the_next_line() {
        let plain = Mesh::parse_obj(OCTAHEDRON_WITH_NORMALS_AND_UVS).unwrap().0;
        let continued = OCTAHEDRON_WITH_NORMALS_AND_UVS
            .replace("v 1 0 0\n", "v 1 \\\n  0 \\\n 0\n")
            .replace("f 1/1/1 3/2/3 5/3/5", "f 1/1/1 \\\r\n3/2/3 5/3/5");
        let (mesh, _) = Mesh::parse_obj(&continued).unwrap();
        assert_eq!(mesh.positions(), plain.positions());
        assert_eq!(mesh.faces(), plain.faces());
        // Lines are still numbered as in the file: the bad vertex is on line 6.
        let text = continued.replace("v 0 1 0\n", "v 0 one 0\n");
        assert!(
            malformed_message(&text).starts_with("line 6: vertex 2: cannot read"),
            "{}",
            malformed_message(&text)
        );
    }

    #[test]
    fn convex_quads_are_triangulated_keeping_their_normals() {
        // The unit cube as six quads, every corner naming its vertex's normal.
        let mut text = String::new();
        for i in 0..8 {
            let p = DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64);
            text += &format!("v {} {} {}\n", p.x, p.y, p.z);
        }
        for i in 0..8 {
            let p = DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64);
            let n = (p - DVec3::splat(0.5)).normalize();
            text += &format!("vn {} {} {}\n", n.x, n.y, n.z);
        }
        for quad in [
            [1, 3, 4, 2],
            [5, 6, 8, 7],
            [1, 2, 6, 5],
            [3, 7, 8, 4],
            [1, 5, 7, 3],
            [2, 4, 8, 6],
        ] {
            let corners: Vec<String> = quad.iter().map(|v| format!("{v}//{v}")).collect();
            text += &format!("f {}\n", corners.join(" "));
        }
        let (mesh, report) = Mesh::parse_obj(&text).unwrap();
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (8, 12));
        assert!(mesh.is_closed());
        assert!(
            report.warnings[0].starts_with("triangulated 6 faces"),
            "{:?}",
            report.warnings
        );
        let normals = mesh.vertex_normals(NormalSource::Obj).unwrap();
        for (n, p) in normals.iter().zip(mesh.positions()) {
            assert!((*n - (*p - DVec3::splat(0.5)).normalize()).length() < 1e-15);
        }
        // A corner without normal is named by its place in the quad.
        let text = text.replace("f 2//2 4//4 8//8 6//6", "f 2//2 4//4 8 6//6");
        let reason = obj_normals_error(&text);
        assert!(
            reason.contains("corner 2 of face 5 (vertex 7) has no normal"),
            "{reason}"
        );
    }

    #[test]
    fn bent_polygons_are_repaired_and_two_corner_faces_refused() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nv 0 0 1\nf 1 2 5\nf 1 2 3 4\n";
        let (mesh, report) = Mesh::parse_obj(text).unwrap();
        assert_eq!(mesh.face_count(), 3);
        assert_eq!(report.repairs[0].first, crate::mesh::Element::Face(1));
        let error = parse_strict_err(text);
        assert!(
            error
                .to_string()
                .starts_with("face 1: it has 4 corners and is not planar"),
            "{error}"
        );
        let error = parse_err("v 0 0 0\nv 1 0 0\nf 1 2\n");
        assert!(
            matches!(
                error,
                Error::NotATriangle {
                    face: 0,
                    corners: 2
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn out_of_range_vertex_names_the_face() {
        let error = parse_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 9\n");
        assert!(
            matches!(
                error,
                Error::VertexIndexOutOfRange {
                    face: 1,
                    vertex: 8,
                    count: 4
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn negative_indices_count_back_from_the_last_vertex() {
        let text = "v 1 0 0\nv 0 1 0\nv 0 0 1\nf -3 -2 -1\nv 0 0 0\nf -1 -2 -3\n";
        let (mesh, _) = Mesh::parse_obj(text).unwrap();
        assert_eq!(mesh.faces(), &[[0, 1, 2], [3, 2, 1]]);
    }

    #[test]
    fn empty_file_is_an_empty_mesh() {
        for text in ["", "# nothing\nv 0 0 0\n"] {
            let error = parse_err(text);
            assert!(matches!(error, Error::EmptyMesh), "{error}");
        }
    }

    #[test]
    fn errors_name_vertices_in_file_order() {
        // The NaN vertex is the file's vertex 3 (0-based), but the fourth used by faces.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 1\nv 1 1 1\nf 5 2 3\nf 1 2 4\n";
        let error = parse_err(text);
        assert!(
            matches!(error, Error::NonFiniteVertex { vertex: 3 }),
            "{error}"
        );
        // A bow-tie whose centre is the file's last vertex.
        let text = "v 1 1 0\nv 1 -1 0\nv -1 -1 0\nv -1 1 0\nv 0 0 0\nf 5 1 4\nf 5 3 2\n";
        let (_, report) = Mesh::parse_obj(text).unwrap();
        assert_eq!(report.repairs[0].first, crate::mesh::Element::Vertex(4));
        let error = parse_strict_err(text);
        assert!(error.to_string().starts_with("vertex 4: "), "{error}");
    }

    #[test]
    fn identical_positions_are_welded_and_unused_vertices_reported() {
        // Two objects, each with its own copy of the shared edge's vertices; one stray vertex.
        let text = "\
o left
v 0 0 0
v 1 0 0
v 0 1 0
f 1 2 3
o right
v 1 0 0
v 0 1 0
v 1 1 0
v 5 5 5
f 4 6 5
";
        let (mesh, report) = Mesh::parse_obj(text).unwrap();
        assert_eq!(mesh.vertex_count(), 4);
        assert_eq!(report.welded, 2);
        assert_eq!(report.warnings, vec!["dropped 1 vertices used by no face"]);
        assert_eq!(mesh.edge_count(), 5);
        assert_eq!(mesh.neighbor(0, 1), Some((1, 2)));
    }

    #[test]
    fn flipped_face_in_a_file_is_reoriented() {
        let text =
            OCTAHEDRON_WITH_NORMALS_AND_UVS.replace("f 3/4/3 2/1/2 5/2/5", "f 2/1/2 3/4/3 5/2/5");
        let (mesh, report) = Mesh::parse_obj(&text).unwrap();
        assert_eq!(report.reoriented_faces, 1);
        assert!(
            report.warnings[0].contains("face 1"),
            "{:?}",
            report.warnings
        );
        assert_eq!(mesh.faces()[1], [1, 4, 2]);
        // The file's normals still belong to their vertices.
        assert!(mesh.vertex_normals(NormalSource::Obj).is_ok());
    }

    #[test]
    fn polylines_are_ignored_with_a_warning() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\nf 1 2 3\n";
        let (mesh, report) = Mesh::parse_obj(text).unwrap();
        assert_eq!(mesh.face_count(), 1);
        assert_eq!(report.warnings, vec!["ignored 1 polyline (l) records"]);
    }

    #[test]
    fn a_byte_order_mark_does_not_hide_the_first_vertex() {
        let plain = Mesh::parse_obj(OCTAHEDRON_WITH_NORMALS_AND_UVS).unwrap().0;
        // The mark right before the first `v` record, and before a comment line.
        let bare = OCTAHEDRON_WITH_NORMALS_AND_UVS
            .lines()
            .skip(1)
            .map(|l| format!("{l}\n"))
            .collect::<String>();
        for text in [
            format!("\u{feff}{bare}"),
            format!("\u{feff}{OCTAHEDRON_WITH_NORMALS_AND_UVS}"),
        ] {
            assert!(text.starts_with("\u{feff}"));
            let (mesh, report) = Mesh::parse_obj(&text).unwrap();
            assert_eq!(mesh.positions(), plain.positions());
            assert_eq!(mesh.faces(), plain.faces());
            assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        }
        // Through a file, as the command line reads it.
        let path = std::env::temp_dir().join(format!("smoothlab-bom-{}.obj", std::process::id()));
        std::fs::write(&path, format!("\u{feff}{bare}")).unwrap();
        let loaded = Mesh::load_obj(&path);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(loaded.unwrap().0.positions(), plain.positions());
    }

    #[test]
    fn cr_and_crlf_line_ends_parse_like_lf() {
        let plain = Mesh::parse_obj(OCTAHEDRON_WITH_NORMALS_AND_UVS).unwrap().0;
        for end in ["\r", "\r\n"] {
            let text = OCTAHEDRON_WITH_NORMALS_AND_UVS.replace('\n', end);
            let (mesh, report) = Mesh::parse_obj(&text).unwrap();
            assert_eq!(mesh.positions(), plain.positions(), "{end:?}");
            assert_eq!(mesh.faces(), plain.faces(), "{end:?}");
            assert!(report.warnings.is_empty(), "{end:?}: {:?}", report.warnings);
            // The file's normals survive too.
            assert_eq!(
                mesh.vertex_normals(NormalSource::Obj).unwrap(),
                plain.vertex_normals(NormalSource::Obj).unwrap()
            );
        }
    }

    #[test]
    fn signed_zero_and_one_ulp_copies_in_a_file_weld() {
        // The octahedron as two objects, upper and lower half, each with its own copies of
        // the four equator vertices: the lower half writes 0 as -0 and 1 one ulp off.
        let upper = "o upper\nv 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n\
                     f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\n";
        let lower = "o lower\nv 1.0000000000000002 -0 -0\nv -1 -0.0 0\nv -0 1 0\nv 0 -1 -0\n\
                     v 0 0 -1\nf 8 6 10\nf 7 8 10\nf 9 7 10\nf 6 9 10\n";
        let (mesh, report) = Mesh::parse_obj(&format!("{upper}{lower}")).unwrap();
        assert!(mesh.is_closed());
        assert_eq!(mesh.vertex_count(), 6);
        assert_eq!((report.welded, report.welded_near), (4, 1));
        assert_eq!(report.weld_max_distance, f64::EPSILON);
        assert!(
            crate::schemes::build("hb", &mesh, &[]).is_ok(),
            "hb refuses the welded octahedron"
        );
    }

    fn obj_normals_error(text: &str) -> String {
        let (mesh, _) = Mesh::parse_obj(text).unwrap();
        match mesh.vertex_normals(NormalSource::Obj) {
            Err(Error::MissingNormals { reason }) => reason,
            other => panic!("expected MissingNormals, got {other:?}"),
        }
    }

    #[test]
    fn contradictory_normals_name_the_vertex() {
        // Face 5 gives vertex 2 (file vertex 3, 0-based 2) a normal 1e-5 rad off.
        let text = OCTAHEDRON_WITH_NORMALS_AND_UVS
            .replace("vn 0 0 -1\n", "vn 0 0 -1\nvn 0 1 0.00001\n")
            .replace("f 3/1/3 1/2/1 6/3/6", "f 3/1/7 1/2/1 6/3/6");
        let reason = obj_normals_error(&text);
        assert!(
            reason.contains("vertex 2 has contradictory normals"),
            "{reason}"
        );
        assert!(reason.contains("faces 0 and 4"), "{reason}");
    }

    #[test]
    fn normals_within_the_tolerance_are_accepted() {
        // 1e-7 rad apart: the same direction written with rounding.
        let text = OCTAHEDRON_WITH_NORMALS_AND_UVS
            .replace("vn 0 0 -1\n", "vn 0 0 -1\nvn 0 1 0.0000001\n")
            .replace("f 3/1/3 1/2/1 6/3/6", "f 3/1/7 1/2/1 6/3/6");
        let (mesh, _) = Mesh::parse_obj(&text).unwrap();
        let normals = mesh.vertex_normals(NormalSource::Obj).unwrap();
        assert_eq!(normals[2], DVec3::Y);
    }

    #[test]
    fn a_corner_without_normal_makes_obj_normals_unusable() {
        let text =
            OCTAHEDRON_WITH_NORMALS_AND_UVS.replace("f 4/3/4 2/4/2 6/1/6", "f 4/3/4 2/4 6/1/6");
        let reason = obj_normals_error(&text);
        assert!(
            reason.contains("corner 1 of face 6 (vertex 1) has no normal"),
            "{reason}"
        );
        // Estimated normals still work.
        let (mesh, _) = Mesh::parse_obj(&text).unwrap();
        assert!(mesh.vertex_normals(NormalSource::Estimate).is_ok());
    }

    #[test]
    fn zero_normal_makes_obj_normals_unusable() {
        let text = OCTAHEDRON_WITH_NORMALS_AND_UVS.replace("vn 0 0 1\n", "vn 0 0 0\n");
        let reason = obj_normals_error(&text);
        assert!(
            reason.contains("vertex 4 has a zero or non-finite normal"),
            "{reason}"
        );
    }

    #[test]
    fn file_without_normals_says_so() {
        let (positions, faces) = generate::tetrahedron();
        let (mesh, _) = Mesh::from_triangles(positions, faces).unwrap();
        let reason = obj_normals_error(&mesh.to_obj(""));
        assert_eq!(reason, "the OBJ file has no normals");
    }
}
