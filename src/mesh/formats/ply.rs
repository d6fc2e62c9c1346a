//! PLY (Polygon File Format) input through the `ply-rs-bw` crate: ASCII, binary little endian
//! and binary big endian.
//!
//! Read: the `vertex` element's `x`, `y`, `z` properties (any numeric type) and the `face`
//! element's `vertex_indices` (or `vertex_index`) list (any integer type). Every other element
//! and property (normals, colours, texture coordinates, edges, materials) is skipped.
//! Vertices and faces are numbered from 0 in file order.

use std::path::Path;

use glam::DVec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};

use super::{MeshFormat, malformed};
use crate::error::{Error, Result};
use crate::mesh::polygon::PolygonMesh;

/// The names a face's list of vertex indices goes by.
const INDEX_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// One `vertex` element: the coordinates, NaN until set.
struct PlyVertex([f64; 3]);

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex([f64::NAN; 3])
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return PropertyAccessResult::Ignored,
        };
        self.0[axis] = match property {
            Property::Char(v) => v.into(),
            Property::UChar(v) => v.into(),
            Property::Short(v) => v.into(),
            Property::UShort(v) => v.into(),
            Property::Int(v) => v.into(),
            Property::UInt(v) => v.into(),
            Property::Float(v) => v.into(),
            Property::Double(v) => v,
            _ => return PropertyAccessResult::UnsupportedType,
        };
        PropertyAccessResult::Set
    }
}

/// One `face` element: its vertex indices (wide enough for any PLY integer type).
struct PlyFace(Vec<i64>);

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace(Vec::new())
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if !INDEX_LISTS.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        self.0 = match property {
            Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
            Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
            Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
            _ => return PropertyAccessResult::UnsupportedType,
        };
        PropertyAccessResult::Set
    }
}

/// Any other element: read past and dropped.
struct Skipped;

impl PropertyAccess for Skipped {
    fn new() -> Self {
        Skipped
    }
}

/// Checks that the header declares what smoothlab reads, with usable types.
fn check_header(header: &Header) -> std::result::Result<(), String> {
    let vertex = header
        .elements
        .get("vertex")
        .ok_or("the header declares no 'vertex' element")?;
    for axis in ["x", "y", "z"] {
        match vertex.properties.get(axis).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List(..)) => {
                return Err(format!("vertex property '{axis}' is a list, not a number"));
            }
            None => return Err(format!("the 'vertex' element has no '{axis}' property")),
        }
    }
    let face = header.elements.get("face").ok_or(
        "the header declares no 'face' element (a point cloud has no surface to build on)",
    )?;
    let list = INDEX_LISTS
        .iter()
        .find_map(|name| face.properties.get(*name))
        .ok_or("the 'face' element has no 'vertex_indices' list")?;
    match list.data_type {
        PropertyType::List(_, ScalarType::Float | ScalarType::Double) | PropertyType::Scalar(_) => {
            Err(format!(
                "face property '{}' is not a list of integers",
                list.name
            ))
        }
        PropertyType::List(..) => Ok(()),
    }
}

/// A `ply-rs-bw` error on one line: its first line (what was being read, with the line
/// number) and its innermost cause.
fn one_line(error: &impl std::fmt::Display) -> String {
    let text = error.to_string();
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    match lines.as_slice() {
        [] => "unreadable data".to_string(),
        [only] => only.to_string(),
        [first, .., last] => {
            let cause = last.strip_prefix("Error:").unwrap_or(last).trim();
            format!("{first} {cause}")
        }
    }
}

/// Reads the payload of one element with a parser for `E`.
fn read_element<E: PropertyAccess>(
    reader: &mut Reader<&[u8]>,
    element: &ElementDef,
    header: &Header,
) -> std::result::Result<Vec<E>, String> {
    Parser::<E>::new()
        .read_payload_for_element(reader, element, header)
        .map_err(|e| format!("element '{}': {}", element.name, one_line(&e)))
}

/// Parses a PLY file into positions and polygons.
pub(super) fn read(bytes: &[u8], origin: &Path) -> Result<PolygonMesh> {
    let bad = |message: String| malformed(origin, MeshFormat::Ply, message);
    let mut reader = Reader::new(bytes);
    let header = Parser::<Skipped>::new()
        .read_header(&mut reader)
        .map_err(|e| bad(format!("bad header: {}", one_line(&e))))?;
    check_header(&header).map_err(|e| bad(format!("bad header: {e}")))?;
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    // Elements are stored one after the other in header order.
    for element in header.elements.values() {
        match element.name.as_str() {
            "vertex" => {
                vertices = read_element::<PlyVertex>(&mut reader, element, &header).map_err(bad)?
            }
            "face" => {
                faces = read_element::<PlyFace>(&mut reader, element, &header).map_err(bad)?
            }
            _ => {
                read_element::<Skipped>(&mut reader, element, &header).map_err(bad)?;
            }
        }
    }
    let mut mesh = PolygonMesh {
        positions: vertices
            .into_iter()
            .map(|v| DVec3::from_array(v.0))
            .collect(),
        ..Default::default()
    };
    let count = mesh.positions.len();
    let mut corners = Vec::new();
    for (face, PlyFace(indices)) in faces.iter().enumerate() {
        corners.clear();
        for &index in indices {
            if index < 0 {
                return Err(bad(format!("face {face} refers to vertex {index}")));
            }
            let index = u32::try_from(index).map_err(|_| Error::VertexIndexOutOfRange {
                face,
                vertex: index as usize,
                count,
            })?;
            corners.push(index);
        }
        mesh.push_polygon(&corners);
    }
    Ok(mesh)
}
