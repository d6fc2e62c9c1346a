//! OFF (Object File Format, ASCII) input.
//!
//! Read by hand: the format is a keyword line, a count line and one line per vertex and face,
//! and no maintained crate reads it with errors that name the line at fault.
//!
//! Accepted: the keyword `OFF` with the optional prefixes `ST`, `C`, `N` (texture
//! coordinates, colours and normals after each vertex's x y z, which are ignored), the counts
//! on the keyword line or the next one, `#` comments and blank lines anywhere, and face colours
//! after a face's indices (ignored). Refused with an error: binary OFF, 4-D and n-D variants,
//! missing or unreadable numbers and content after the last face. Vertices are numbered from 0
//! in file order, faces in file order.

use std::path::Path;

use glam::DVec3;

use super::{MeshFormat, malformed, numbered_lines};
use crate::error::{Error, Result};
use crate::mesh::polygon::PolygonMesh;

/// The lines of the file that carry data: 1-based line number and the words before any `#`.
fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    numbered_lines(text).filter_map(|(number, line)| {
        let data = line.split('#').next().unwrap_or("");
        let words: Vec<&str> = data.split_whitespace().collect();
        (!words.is_empty()).then_some((number, words))
    })
}

/// Parses an OFF file into positions and polygons.
pub(super) fn read(bytes: &[u8], origin: &Path) -> Result<PolygonMesh> {
    let bad = |message: String| malformed(origin, MeshFormat::Off, message);
    let text = std::str::from_utf8(bytes)
        .map_err(|e| bad(format!("not ASCII text ({e}); binary OFF is not supported")))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = data_lines(text);
    let Some((line, words)) = lines.next() else {
        return Err(bad("the file is empty (expected 'OFF')".to_string()));
    };
    let keyword = words[0];
    let prefix = keyword.strip_suffix("OFF").ok_or_else(|| {
        bad(format!(
            "line {line}: bad header: expected the keyword 'OFF', found '{keyword}'"
        ))
    })?;
    if !["", "ST", "C", "N", "NC", "CN", "STC", "STN", "STNC", "STCN"].contains(&prefix) {
        return Err(bad(format!(
            "line {line}: the OFF variant '{keyword}' is not supported (only 3-D OFF with \
             optional ST, C, N prefixes)"
        )));
    }
    if words.get(1) == Some(&"BINARY") {
        return Err(bad(format!("line {line}: binary OFF is not supported")));
    }
    // The counts follow the keyword on its line or on the next data line.
    let (line, counts) = if words.len() > 1 {
        (line, words[1..].to_vec())
    } else {
        lines
            .next()
            .ok_or_else(|| bad("the file ends before the vertex and face counts".to_string()))?
    };
    if counts.len() < 2 {
        return Err(bad(format!(
            "line {line}: expected the vertex, face and edge counts, found '{}'",
            counts.join(" ")
        )));
    }
    let count = |k: usize, what: &str| -> Result<usize> {
        counts[k].parse().map_err(|_| {
            bad(format!(
                "line {line}: the {what} count '{}' is not a whole number ≥ 0",
                counts[k]
            ))
        })
    };
    let (vertex_count, face_count) = (count(0, "vertex")?, count(1, "face")?);

    let mut mesh = PolygonMesh::default();
    // The counts are the file's claim: allocate for what the text can hold at most.
    let lines_left = text.len() / 2;
    mesh.positions.reserve(vertex_count.min(lines_left));
    for vertex in 0..vertex_count {
        let (line, words) = lines.next().ok_or_else(|| {
            bad(format!(
                "the file ends after {vertex} of the {vertex_count} vertices"
            ))
        })?;
        if words.len() < 3 {
            return Err(bad(format!(
                "line {line}: vertex {vertex} has {} coordinates, expected 3",
                words.len()
            )));
        }
        let mut xyz = [0.0; 3];
        for (k, word) in words[..3].iter().enumerate() {
            xyz[k] = word.parse().map_err(|_| {
                bad(format!(
                    "line {line}: vertex {vertex}: cannot read coordinate '{word}'"
                ))
            })?;
        }
        mesh.positions.push(DVec3::from_array(xyz));
    }
    mesh.arities.reserve(face_count.min(lines_left));
    let mut corners = Vec::new();
    for face in 0..face_count {
        let (line, words) = lines.next().ok_or_else(|| {
            bad(format!(
                "the file ends after {face} of the {face_count} faces"
            ))
        })?;
        let arity: usize = words[0].parse().map_err(|_| {
            bad(format!(
                "line {line}: face {face}: cannot read the corner count '{}'",
                words[0]
            ))
        })?;
        // Compared without `arity + 1`, which overflows for a count near the integer limit.
        let listed = words.len() - 1;
        if listed < arity {
            return Err(bad(format!(
                "line {line}: face {face} announces {arity} corners but lists {listed}"
            )));
        }
        corners.clear();
        for word in &words[1..=arity] {
            let index: u64 = word.parse().map_err(|_| {
                bad(format!(
                    "line {line}: face {face}: cannot read vertex index '{word}'"
                ))
            })?;
            let index = u32::try_from(index).map_err(|_| Error::VertexIndexOutOfRange {
                face,
                vertex: index as usize,
                count: vertex_count,
            })?;
            corners.push(index);
        }
        mesh.push_polygon(&corners);
    }
    if let Some((line, words)) = lines.next() {
        return Err(bad(format!(
            "line {line}: unexpected '{}' after the last of the {face_count} faces",
            words.join(" ")
        )));
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use crate::error::Error;
    use crate::mesh::{LoadOptions, Mesh, MeshFormat};

    /// A unit cube as six quads, with comments, blank lines, counts on their own line and a
    /// face colour.
    const CUBE: &str = "OFF
# a cube
8 6 12

0 0 0
1 0 0
0 1 0
1 1 0
0 0 1   # vertex 4
1 0 1
0 1 1
1 1 1
4 0 2 3 1
4 4 5 7 6 255 0 0
4 0 1 5 4
4 2 6 7 3
4 0 4 6 2
4 1 3 7 5
";

    fn parse(text: &str) -> crate::error::Result<(Mesh, crate::mesh::LoadReport)> {
        Mesh::parse_format(text.as_bytes(), MeshFormat::Off, &LoadOptions::default())
    }

    fn message(text: &str) -> String {
        match parse(text).unwrap_err() {
            Error::MalformedMesh {
                format: "OFF",
                message,
                ..
            } => message,
            other => panic!("expected a malformed OFF, got {other:?}"),
        }
    }

    #[test]
    fn a_quad_cube_loads_triangulated() {
        let (mesh, report) = parse(CUBE).unwrap();
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (8, 12));
        assert!(mesh.is_closed());
        assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
        assert!(report.warnings[0].starts_with("triangulated 6 faces"));
        // Counts on the keyword line, and the colour-and-normal variant, read the same.
        let inline = CUBE.replacen("OFF\n# a cube\n8 6 12", "OFF 8 6 12", 1);
        assert_eq!(parse(&inline).unwrap().0.faces(), mesh.faces());
    }

    #[test]
    fn vertex_extras_of_the_variants_are_ignored() {
        let text = "CNOFF\n4 4 6\n0 0 0 1 0 0 0 0 1\n1 0 0 1 0 0 0 0 1\n0 1 0 1 0 0 0 0 1\n\
                    0 0 1 1 0 0 0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
        let (mesh, _) = parse(text).unwrap();
        assert_eq!(mesh.positions()[3], glam::DVec3::Z);
        assert!(mesh.is_closed());
    }

    #[test]
    fn malformed_files_name_the_line_and_element() {
        assert_eq!(message(""), "the file is empty (expected 'OFF')");
        assert!(message("PLY\n8 6 12\n").contains("line 1: bad header"));
        assert!(message("4OFF\n1 1 0\n").contains("'4OFF' is not supported"));
        assert!(message("OFF BINARY\n").contains("binary OFF is not supported"));
        assert!(message("OFF\n8\n").contains("line 2: expected the vertex, face"));
        assert!(message("OFF\nx 6 12\n").contains("the vertex count 'x' is not a whole number"));
        assert!(message("OFF\n-8 6 12\n").contains("line 2: the vertex count '-8' is not a whole"));
        assert!(message("OFF\n8 -6 12\n").contains("line 2: the face count '-6' is not a whole"));
        // Truncated: the counts promise more than the file holds.
        assert_eq!(
            message("OFF\n4000000000 4000000000 0\n"),
            "the file ends after 0 of the 4000000000 vertices"
        );
        let truncated: String = CUBE.lines().take(9).map(|l| format!("{l}\n")).collect();
        assert_eq!(
            message(&truncated),
            "the file ends after 5 of the 8 vertices"
        );
        let no_faces: String = CUBE.lines().take(15).map(|l| format!("{l}\n")).collect();
        assert_eq!(message(&no_faces), "the file ends after 3 of the 6 faces");
        assert!(
            message(&CUBE.replace("1 1 0\n", "1 one 0\n"))
                .contains("line 8: vertex 3: cannot read coordinate 'one'")
        );
        assert!(message(&CUBE.replace("1 1 0\n", "1 1\n")).contains("vertex 3 has 2 coordinates"));
        assert!(
            message(&CUBE.replace("4 0 1 5 4", "4 0 1 5"))
                .contains("line 15: face 2 announces 4 corners but lists 3")
        );
        assert!(
            message(&CUBE.replace("4 0 1 5 4", "4 0 1 5 -4"))
                .contains("face 2: cannot read vertex index '-4'")
        );
        assert!(message(&format!("{CUBE}3 0 1 2\n")).contains("line 19: unexpected '3 0 1 2'"));
        let binary = Mesh::parse_format(b"OFF\n\xff\x00", MeshFormat::Off, &Default::default());
        assert!(
            binary.unwrap_err().to_string().contains("not ASCII text"),
            "non-text bytes"
        );
    }

    #[test]
    fn bad_indices_and_coordinates_are_typed_errors() {
        assert!(matches!(
            parse(&CUBE.replace("4 0 1 5 4", "4 0 1 5 8")).unwrap_err(),
            Error::VertexIndexOutOfRange {
                face: 2,
                vertex: 8,
                count: 8
            }
        ));
        assert!(matches!(
            parse(&CUBE.replace("4 0 1 5 4", "4 0 1 5 4294967296")).unwrap_err(),
            Error::VertexIndexOutOfRange { face: 2, .. }
        ));
        for nan in ["nan", "NaN", "inf"] {
            assert!(matches!(
                parse(&CUBE.replace("1 1 0\n", &format!("1 {nan} 0\n"))).unwrap_err(),
                Error::NonFiniteVertex { vertex: 3 }
            ));
        }
        assert!(matches!(
            parse("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n").unwrap_err(),
            Error::NotATriangle {
                face: 0,
                corners: 2
            }
        ));
    }

    #[test]
    fn a_corner_count_at_the_integer_limit_names_the_face() {
        let text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n18446744073709551615 0 1 2\n";
        assert_eq!(
            message(text),
            "line 6: face 0 announces 18446744073709551615 corners but lists 3"
        );
        // One past the limit is no number of corners at all.
        let text = text.replace("18446744073709551615", "18446744073709551616");
        assert!(message(&text).contains("line 6: face 0: cannot read the corner count"));
    }

    #[test]
    fn cr_and_crlf_line_ends_parse_like_lf() {
        let (plain, _) = parse(CUBE).unwrap();
        for end in ["\r", "\r\n"] {
            let (mesh, _) = parse(&CUBE.replace('\n', end)).unwrap();
            assert_eq!(mesh.positions(), plain.positions(), "{end:?}");
            assert_eq!(mesh.faces(), plain.faces(), "{end:?}");
        }
        // Line numbers count a CR LF pair once.
        let text = CUBE.replace("1 1 0\n", "1 one 0\n").replace('\n', "\r\n");
        assert!(
            message(&text).contains("line 8: vertex 3"),
            "{}",
            message(&text)
        );
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        for end in 0..CUBE.len() {
            // Cuts that only drop trailing whitespace leave a valid file.
            if CUBE[end..].trim().is_empty() {
                continue;
            }
            assert!(parse(&CUBE[..end]).is_err(), "prefix of {end} bytes parsed");
        }
    }
}
