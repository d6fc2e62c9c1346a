//! STL (stereolithography) input through the `stl_io` crate, ASCII and binary.
//!
//! STL stores every facet as three separate single-precision positions and shares none, so
//! the reader makes vertex `3·f + c` of corner `c` of facet `f`, and welding (identical
//! positions always, close ones within [`crate::mesh::LoadOptions::weld_tolerance`]) makes the
//! facets a connected mesh. Errors name vertices by that number. Coordinates are single
//! precision in both encodings (`stl_io` reads ASCII numbers as `f32` too). Facet normals are
//! ignored: the orientation comes from the corner order, as for every format.
//!
//! The encoding is decided by size rather than by the `solid` keyword, which many binary files
//! start their header with: a file whose length is exactly 84 bytes plus 50 per facet counted
//! in its header is binary; otherwise a text file starting with `solid` is ASCII (of which only
//! the first solid is read), and anything else is a truncated or padded binary file, also when
//! its header starts with `solid`.

use std::io::Cursor;
use std::path::Path;

use glam::DVec3;

use super::{MeshFormat, malformed};
use crate::error::Result;
use crate::mesh::polygon::PolygonMesh;

/// Bytes before the first facet of a binary file: an 80-byte header and the facet count.
const BINARY_HEADER: usize = 84;
/// Bytes per facet of a binary file: normal, three corners (12 f32) and an attribute count.
const BINARY_FACET: usize = 50;

/// Parses an STL file into one triangle per facet.
pub(super) fn read(bytes: &[u8], origin: &Path) -> Result<PolygonMesh> {
    let bad = |message: String| malformed(origin, MeshFormat::Stl, message);
    let announced = bytes
        .get(80..BINARY_HEADER)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    let binary_size = announced.map(|n| BINARY_HEADER as u128 + (BINARY_FACET * n) as u128);
    let solid = bytes.trim_ascii_start().starts_with(b"solid");
    // ASCII is text: a file starting with `solid` that holds other bytes is a binary file
    // whose header starts with the word, and whose size is wrong.
    let text = |b: &u8| b.is_ascii_graphic() || b.is_ascii_whitespace() || !b.is_ascii();
    let ascii = solid && std::str::from_utf8(bytes).is_ok() && bytes.iter().all(text);
    let mut data: Vec<u8>;
    if binary_size == Some(bytes.len() as u128) {
        // stl_io takes a header starting with "solid " for ASCII: blank the header, which
        // carries nothing smoothlab reads.
        data = bytes.to_vec();
        data[..80].fill(b' ');
    } else if ascii {
        // stl_io wants the keyword at the start of the first line, followed by a space.
        let text = bytes.trim_ascii_start();
        data = b"solid ".to_vec();
        data.extend_from_slice(&text[5..]);
    } else {
        let not_ascii = if solid {
            "not ASCII (it starts with 'solid' but holds binary data)"
        } else {
            "not ASCII (no 'solid' keyword)"
        };
        return Err(bad(match (announced, binary_size) {
            (Some(n), Some(size)) => format!(
                "{not_ascii}, and as binary the header announces {n} facets ({size} bytes) but \
                 the file has {} bytes: truncated, padded or not STL",
                bytes.len()
            ),
            _ => format!(
                "{not_ascii} and {} bytes, shorter than the {BINARY_HEADER}-byte binary header",
                bytes.len()
            ),
        }));
    }
    let mut cursor = Cursor::new(data.as_slice());
    let facets =
        stl_io::create_stl_reader(&mut cursor).map_err(|e| bad(format!("bad header: {e}")))?;
    let mut mesh = PolygonMesh::default();
    for (facet, triangle) in facets.enumerate() {
        let triangle = triangle.map_err(|e| bad(format!("facet {facet}: {e}")))?;
        let first = mesh.positions.len() as u32;
        mesh.positions.extend(
            triangle
                .vertices
                .iter()
                .map(|v| DVec3::new(v[0].into(), v[1].into(), v[2].into())),
        );
        mesh.push_polygon(&[first, first + 1, first + 2]);
    }
    Ok(mesh)
}
