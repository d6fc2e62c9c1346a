//! Wavefront OBJ input (through tobj) and output.
//!
//! smoothlab reads only geometry: `v`, `vn` and `f` records. Object, group and material
//! statements are dropped before tobj sees the text, so the file is one model and tobj's vertex
//! numbering follows the file; polyline (`l`) records are dropped with a warning. tobj is run
//! with `single_index = false` so that per-corner normal and texture indices never split a
//! vertex, and with `triangulate = false` so that polygons are reported instead of silently
//! split.
//!
//! A light scan of the face records, before tobj, gives what tobj does not expose: the file
//! number of every corner's vertex (so errors can name vertices as the file numbers them,
//! 0-based), range errors naming the face, and which corners have no normal index (tobj fills
//! those with a neighbour's normal, which must not pass as the vertex's normal).

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use super::normals::CornerNormals;
use super::{LoadReport, Mesh, validate};
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
    /// The first (face, corner) written without a normal index.
    first_corner_without_normal: Option<(usize, usize)>,
    /// Number of `l` records dropped.
    polylines: usize,
}

fn malformed(origin: &Path, message: String) -> Error {
    Error::MalformedObj {
        path: origin.to_path_buf(),
        message,
    }
}

fn scan(text: &str, origin: &Path) -> Result<Scan> {
    let mut scan = Scan {
        geometry: String::with_capacity(text.len()),
        vertex_count: 0,
        corner_vertex: Vec::new(),
        has_normals: false,
        first_corner_without_normal: None,
        polylines: 0,
    };
    // Resolved (face, 0-based vertex) per corner; checked once all `v` records are counted
    // because tobj, like many writers, accepts forward references.
    let mut corners: Vec<(usize, i64)> = Vec::new();
    let mut face = 0;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        if DROPPED_STATEMENTS.contains(&keyword) {
            continue;
        }
        match keyword {
            "l" => {
                scan.polylines += 1;
                continue;
            }
            "v" => scan.vertex_count += 1,
            "vn" => scan.has_normals = true,
            "f" => {
                for (corner, word) in words.enumerate() {
                    let mut fields = word.split('/');
                    let position = fields.next().unwrap_or("");
                    let index: i64 = position.parse().map_err(|_| {
                        malformed(origin, format!("face {face}: cannot read vertex '{word}'"))
                    })?;
                    let resolved = match index {
                        0 => {
                            return Err(malformed(
                                origin,
                                format!("face {face}: vertex index 0 (OBJ counts from 1)"),
                            ));
                        }
                        // Negative indices count back from the last vertex read so far.
                        i if i < 0 => scan.vertex_count as i64 + i,
                        i => i - 1,
                    };
                    corners.push((face, resolved));
                    let has_normal = fields.nth(1).is_some_and(|n| !n.is_empty());
                    if !has_normal && scan.first_corner_without_normal.is_none() {
                        scan.first_corner_without_normal = Some((face, corner));
                    }
                }
                face += 1;
            }
            _ => {}
        }
        scan.geometry.push_str(line);
        scan.geometry.push('\n');
    }
    for &(face, vertex) in &corners {
        if vertex < 0 {
            return Err(malformed(
                origin,
                format!("face {face} refers to a vertex before the first one"),
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
    scan.corner_vertex = corners.iter().map(|&(_, v)| v as u32).collect();
    Ok(scan)
}

/// Parses OBJ text; `origin` names the file in errors.
pub(super) fn parse(text: &str, origin: &Path) -> Result<(Mesh, LoadReport)> {
    let scan = scan(text, origin)?;
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: false,
        ignore_lines: false,
    };
    // Materials were dropped with their statements, so the loader is never asked for one.
    let (models, _materials) = tobj::load_obj_buf(&mut scan.geometry.as_bytes(), &options, |_| {
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
    if let Some((face, &corners)) = arities.iter().enumerate().find(|(_, a)| **a != 3) {
        return Err(Error::NotATriangle {
            face,
            corners: corners as usize,
        });
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
    // tobj numbers vertices in order of first use; map them back to the file's numbers.
    let mut labels = vec![u32::MAX; positions.len()];
    for (&local, &file) in corners.iter().zip(&scan.corner_vertex) {
        labels[local as usize] = file;
    }
    let corner_normals = if !scan.has_normals {
        Err("the OBJ file has no normals".to_string())
    } else if let Some((face, corner)) = scan.first_corner_without_normal {
        let vertex = scan.corner_vertex[3 * face + corner];
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
    let faces: Vec<[u32; 3]> = corners
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let used_in_file = positions.len();
    let (mesh, mut report) = validate::assemble(positions, faces, Some(&labels), corner_normals)?;
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
