//! PLY (Polygon File Format) input: ASCII, binary little endian and binary big endian.
//!
//! Read by hand, so that every error is one sentence naming the header line, or the element
//! with its line (ASCII) or byte offset (binary), and so that nothing is allocated by a count
//! the file declares beyond what its size can hold.
//!
//! Read: the `vertex` element's `x`, `y`, `z` properties (any numeric type) and the `face`
//! element's `vertex_indices` (or `vertex_index`) list (any integer type). Every other element
//! and property (normals, colours, texture coordinates, edges, materials) is read past and
//! dropped. Header lines end in LF, CR LF or CR; `comment` and `obj_info` lines are skipped.
//! Refused with an error: data missing or left over after the elements the header declares,
//! numbers that do not fit their type. Vertices and faces are numbered from 0 in file order.

use std::path::Path;

use glam::DVec3;

use super::{MeshFormat, malformed, numbered_lines};
use crate::error::Result;
use crate::mesh::polygon::PolygonMesh;

/// The names a face's list of vertex indices goes by.
const INDEX_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type of a header type name (old and new spellings).
    fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Bytes per value in a binary file.
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The range of an integer type; None for the floating-point types.
    fn integer_range(self) -> Option<(i64, i64)> {
        Some(match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => return None,
        })
    }
}

/// How the data after the header is encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

/// A property's type: one number, or a list of numbers preceded by its length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PropertyType {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// One `property` line.
#[derive(Clone, Debug)]
struct PropertyDef {
    name: String,
    kind: PropertyType,
}

/// One `element` line and its properties.
#[derive(Clone, Debug)]
struct ElementDef {
    name: String,
    count: usize,
    properties: Vec<PropertyDef>,
}

/// The header: the encoding, the elements in file order, and where the data starts.
struct Header {
    encoding: Encoding,
    elements: Vec<ElementDef>,
    /// Byte offset of the first data byte.
    data_start: usize,
    /// Number of header lines (the data's first line is the next one).
    lines: usize,
}

/// The lines of the header, split at LF, CR LF or a lone CR, with the offset after each.
fn header_lines(bytes: &[u8]) -> impl Iterator<Item = (&[u8], usize)> {
    let mut start = 0;
    std::iter::from_fn(move || {
        if start >= bytes.len() {
            return None;
        }
        let rest = &bytes[start..];
        let (line, next) = match rest.iter().position(|&b| b == b'\n' || b == b'\r') {
            Some(end) if rest[end..].starts_with(b"\r\n") => (&rest[..end], start + end + 2),
            Some(end) => (&rest[..end], start + end + 1),
            None => (rest, bytes.len()),
        };
        start = next;
        Some((line, next))
    })
}

/// Parses the header; the message names the line at fault.
fn read_header(bytes: &[u8]) -> std::result::Result<Header, String> {
    let mut lines = header_lines(bytes);
    match lines.next() {
        None => return Err("the file is empty (expected 'ply')".to_string()),
        Some((b"ply", _)) => {}
        Some((line, _)) => {
            return Err(format!(
                "line 1: expected 'ply', found '{}'",
                String::from_utf8_lossy(line).trim()
            ));
        }
    }
    let mut encoding = None;
    let mut elements: Vec<ElementDef> = Vec::new();
    for (index, (raw, end)) in lines.enumerate() {
        let number = index + 2;
        let line = std::str::from_utf8(raw)
            .map_err(|_| format!("line {number} is not text (no 'end_header' before it)"))?;
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = |message: String| format!("line {number}: {message}");
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["end_header"] => {
                let encoding =
                    encoding.ok_or_else(|| at("'end_header' before any 'format' line".into()))?;
                return Ok(Header {
                    encoding,
                    elements,
                    data_start: end,
                    lines: number,
                });
            }
            ["format", name, _version] => {
                encoding = Some(match *name {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::LittleEndian,
                    "binary_big_endian" => Encoding::BigEndian,
                    other => {
                        return Err(at(format!(
                            "unknown format '{other}' (expected ascii, binary_little_endian or \
                             binary_big_endian)"
                        )));
                    }
                })
            }
            ["element", name, count] => {
                let count = count.parse().map_err(|_| {
                    at(format!(
                        "the count of element '{name}', '{count}', is not a whole number ≥ 0"
                    ))
                })?;
                elements.push(ElementDef {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", rest @ ..] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| at("a property before any 'element' line".into()))?;
                let scalar = |name: &str| {
                    Scalar::from_name(name)
                        .ok_or_else(|| at(format!("unknown property type '{name}'")))
                };
                let (kind, name) = match rest {
                    ["list", count, item, name] => {
                        let count_type = scalar(count)?;
                        if count_type.integer_range().is_none() {
                            return Err(at(format!(
                                "the length of list '{name}' has the type '{count}', not an \
                                 integer type"
                            )));
                        }
                        let item = scalar(item)?;
                        (
                            PropertyType::List {
                                count: count_type,
                                item,
                            },
                            name,
                        )
                    }
                    [kind, name] if *kind != "list" => (PropertyType::Scalar(scalar(kind)?), name),
                    _ => {
                        return Err(at(format!(
                            "expected 'property TYPE NAME' or 'property list COUNT_TYPE \
                             ITEM_TYPE NAME', found '{}'",
                            line.trim()
                        )));
                    }
                };
                element.properties.push(PropertyDef {
                    name: name.to_string(),
                    kind,
                });
            }
            _ => return Err(at(format!("unexpected header line '{}'", line.trim()))),
        }
    }
    Err("the file ends before the 'end_header' line".to_string())
}

/// Checks that the header declares what smoothlab reads, with usable types.
fn check_header(header: &Header) -> std::result::Result<(), String> {
    let element = |name: &str| header.elements.iter().find(|e| e.name == name);
    let property =
        |e: &ElementDef, name: &str| e.properties.iter().find(|p| p.name == name).map(|p| p.kind);
    let vertex = element("vertex").ok_or("the header declares no 'vertex' element")?;
    for axis in ["x", "y", "z"] {
        match property(vertex, axis) {
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List { .. }) => {
                return Err(format!("vertex property '{axis}' is a list, not a number"));
            }
            None => return Err(format!("the 'vertex' element has no '{axis}' property")),
        }
    }
    let face = element("face").ok_or(
        "the header declares no 'face' element (a point cloud has no surface to build on)",
    )?;
    let (name, kind) = INDEX_LISTS
        .iter()
        .find_map(|name| Some((name, property(face, name)?)))
        .ok_or("the 'face' element has no 'vertex_indices' list")?;
    match kind {
        PropertyType::List { item, .. } if item.integer_range().is_some() => Ok(()),
        _ => Err(format!("face property '{name}' is not a list of integers")),
    }
}

/// The numbers of the data, read one value at a time in the order the header declares them.
trait Values {
    /// Starts the next element instance; false at the end of the data. Its place (see
    /// [`Values::place`]) is where the instance starts.
    fn start(&mut self) -> bool;
    /// The next value, of type `kind`, as f64 (exact for every PLY integer type).
    fn scalar(&mut self, kind: Scalar) -> std::result::Result<f64, String>;
    /// Checks that a list of `count` values of type `item` can be in the rest of the data,
    /// before anything is read or allocated for it.
    fn check_list(&self, count: usize, item: Scalar) -> std::result::Result<(), String>;
    /// Ends an element instance: an ASCII line must have no values left.
    fn end(&mut self) -> std::result::Result<(), String>;
    /// Where the reader is, for messages: `line N` or `byte N`.
    fn place(&self) -> String;
    /// An upper bound on the number of element instances the rest of the data can hold.
    fn capacity(&self) -> usize;
    /// A description of data left after the last element, if any.
    fn rest(&mut self) -> Option<String>;
}

/// ASCII data: one element instance per line, values separated by white space.
struct AsciiValues<'a> {
    lines: Box<dyn Iterator<Item = (usize, &'a str)> + 'a>,
    line: usize,
    words: std::str::SplitWhitespace<'a>,
    remaining_bytes: usize,
}

impl<'a> AsciiValues<'a> {
    fn new(text: &'a str, header_lines: usize) -> Self {
        AsciiValues {
            lines: Box::new(
                numbered_lines(text)
                    .map(move |(n, l)| (n + header_lines, l))
                    .filter(|(_, l)| !l.trim().is_empty()),
            ),
            line: header_lines,
            words: "".split_whitespace(),
            remaining_bytes: text.len(),
        }
    }
}

impl Values for AsciiValues<'_> {
    fn start(&mut self) -> bool {
        let Some((number, line)) = self.lines.next() else {
            return false;
        };
        self.line = number;
        self.words = line.split_whitespace();
        self.remaining_bytes = self.remaining_bytes.saturating_sub(line.len() + 1);
        true
    }

    fn scalar(&mut self, kind: Scalar) -> std::result::Result<f64, String> {
        let word = self
            .words
            .next()
            .ok_or_else(|| "the line ends before the value".to_string())?;
        match kind.integer_range() {
            Some((low, high)) => {
                let value: i64 = word
                    .parse()
                    .map_err(|_| format!("cannot read '{word}' as an integer"))?;
                if !(low..=high).contains(&value) {
                    return Err(format!(
                        "{value} is outside the type's range {low}..={high}"
                    ));
                }
                Ok(value as f64)
            }
            None if kind == Scalar::F32 => word
                .parse::<f32>()
                .map(f64::from)
                .map_err(|_| format!("cannot read '{word}' as a number")),
            None => word
                .parse::<f64>()
                .map_err(|_| format!("cannot read '{word}' as a number")),
        }
    }

    fn check_list(&self, count: usize, _item: Scalar) -> std::result::Result<(), String> {
        let left = self.words.clone().count();
        if count > left {
            return Err(format!(
                "the list announces {count} values but the line has {left} more"
            ));
        }
        Ok(())
    }

    fn end(&mut self) -> std::result::Result<(), String> {
        let extra: Vec<&str> = self.words.by_ref().collect();
        if extra.is_empty() {
            Ok(())
        } else {
            Err(format!(
                "'{}' after the values the header declares",
                extra.join(" ")
            ))
        }
    }

    fn place(&self) -> String {
        format!("line {}", self.line)
    }

    fn capacity(&self) -> usize {
        self.remaining_bytes
    }

    fn rest(&mut self) -> Option<String> {
        let (number, line) = self.lines.next()?;
        Some(format!("line {number}: unexpected '{}'", line.trim()))
    }
}

/// Binary data of either byte order.
struct BinaryValues<'a> {
    bytes: &'a [u8],
    offset: usize,
    big_endian: bool,
}

impl Values for BinaryValues<'_> {
    fn start(&mut self) -> bool {
        self.offset < self.bytes.len()
    }

    fn scalar(&mut self, kind: Scalar) -> std::result::Result<f64, String> {
        let size = kind.size();
        let raw = self
            .bytes
            .get(self.offset..self.offset + size)
            .ok_or_else(|| "the file ends inside the element".to_string())?;
        self.offset += size;
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(raw);
        if self.big_endian {
            b[..size].reverse();
        }
        Ok(match kind {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    fn check_list(&self, count: usize, item: Scalar) -> std::result::Result<(), String> {
        let left = self.bytes.len() - self.offset;
        let needed = count as u128 * item.size() as u128;
        if needed > left as u128 {
            return Err(format!(
                "the list announces {count} values ({needed} bytes) but the file has {left} \
                 bytes left"
            ));
        }
        Ok(())
    }

    fn end(&mut self) -> std::result::Result<(), String> {
        Ok(())
    }

    fn place(&self) -> String {
        format!("byte {}", self.offset)
    }

    fn capacity(&self) -> usize {
        self.bytes.len() - self.offset
    }

    fn rest(&mut self) -> Option<String> {
        let left = self.bytes.len() - self.offset;
        (left > 0).then(|| format!("{left} bytes from byte {}", self.offset))
    }
}

/// What one property of an element is read into.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Coordinate(usize),
    Corners,
    Skipped,
}

/// Reads every element of the data into positions and polygons.
fn read_data(header: &Header, values: &mut dyn Values) -> std::result::Result<PolygonMesh, String> {
    let mut mesh = PolygonMesh::default();
    let mut corners: Vec<u32> = Vec::new();
    for element in &header.elements {
        let roles: Vec<Role> = element
            .properties
            .iter()
            .map(|p| match (element.name.as_str(), p.name.as_str()) {
                ("vertex", "x") => Role::Coordinate(0),
                ("vertex", "y") => Role::Coordinate(1),
                ("vertex", "z") => Role::Coordinate(2),
                ("face", name) if INDEX_LISTS.contains(&name) => Role::Corners,
                _ => Role::Skipped,
            })
            .collect();
        // The counts are the file's claim: allocate for what the data can hold at most.
        match element.name.as_str() {
            "vertex" => mesh.positions.reserve(element.count.min(values.capacity())),
            "face" => mesh.arities.reserve(element.count.min(values.capacity())),
            _ => {}
        }
        for instance in 0..element.count {
            if !values.start() {
                return Err(format!(
                    "element '{}': the file ends after {instance} of the {} the header declares",
                    element.name, element.count
                ));
            }
            let place = values.place();
            let fail = |message: String| {
                format!("element '{}' {instance} ({place}): {message}", element.name)
            };
            let mut xyz = [f64::NAN; 3];
            corners.clear();
            for (property, &role) in element.properties.iter().zip(&roles) {
                let in_property = |m: String| format!("property '{}': {m}", property.name);
                match property.kind {
                    PropertyType::Scalar(kind) => {
                        let value = values.scalar(kind).map_err(|m| fail(in_property(m)))?;
                        if let Role::Coordinate(axis) = role {
                            xyz[axis] = value;
                        }
                    }
                    PropertyType::List { count, item } => {
                        let length = values.scalar(count).map_err(|m| fail(in_property(m)))?;
                        if length < 0.0 {
                            return Err(fail(in_property(format!("list length {length}"))));
                        }
                        let length = length as usize;
                        values
                            .check_list(length, item)
                            .map_err(|m| fail(in_property(m)))?;
                        for _ in 0..length {
                            let value = values.scalar(item).map_err(|m| fail(in_property(m)))?;
                            if role == Role::Corners {
                                corners.push(corner(value, instance)?);
                            }
                        }
                    }
                }
            }
            values.end().map_err(fail)?;
            match element.name.as_str() {
                "vertex" => mesh.positions.push(DVec3::from_array(xyz)),
                "face" => mesh.push_polygon(&corners),
                _ => {}
            }
        }
    }
    if let Some(rest) = values.rest() {
        let last = header.elements.last().map_or("", |e| e.name.as_str());
        return Err(format!(
            "{rest} after the last element '{last}' (the header declares {} of them)",
            header.elements.last().map_or(0, |e| e.count)
        ));
    }
    Ok(mesh)
}

/// The vertex of a face corner from its index value, an integer of the list's item type (so
/// below 2³²).
fn corner(value: f64, face: usize) -> std::result::Result<u32, String> {
    if value < 0.0 {
        return Err(format!("face {face} refers to vertex {value}"));
    }
    Ok(value as u32)
}

/// Parses a PLY file into positions and polygons.
pub(super) fn read(bytes: &[u8], origin: &Path) -> Result<PolygonMesh> {
    let bad = |message: String| malformed(origin, MeshFormat::Ply, message);
    let header = read_header(bytes).map_err(|e| bad(format!("bad header: {e}")))?;
    check_header(&header).map_err(|e| bad(format!("bad header: {e}")))?;
    let data = &bytes[header.data_start..];
    let result = match header.encoding {
        Encoding::Ascii => {
            let text = std::str::from_utf8(data).map_err(|e| {
                bad(format!(
                    "the data of an ascii file is not text (byte {})",
                    header.data_start + e.valid_up_to()
                ))
            })?;
            read_data(&header, &mut AsciiValues::new(text, header.lines))
        }
        Encoding::LittleEndian | Encoding::BigEndian => read_data(
            &header,
            &mut BinaryValues {
                bytes,
                offset: header.data_start,
                big_endian: header.encoding == Encoding::BigEndian,
            },
        ),
    };
    result.map_err(bad)
}

#[cfg(test)]
mod tests {
    use crate::error::Error;
    use crate::mesh::{LoadOptions, LoadReport, Mesh, MeshFormat};

    /// A tetrahedron with a skipped vertex property and a skipped element.
    const TETRAHEDRON: &str = "ply
format ascii 1.0
comment four faces
element vertex 4
property float x
property float y
property float z
property uchar red
element face 4
property list uchar int vertex_indices
element edge 1
property int vertex1
property int vertex2
end_header
0 0 0 255
1 0 0 0
0 1 0 0
0 0 1 0
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
0 1
";

    /// The tetrahedron's header for `format`, with only the vertex and face elements.
    fn binary_header(format: &str, faces: usize, list: &str) -> Vec<u8> {
        format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\nelement face {faces}\nproperty list {list} vertex_indices\n\
             end_header\n"
        )
        .into_bytes()
    }

    /// The tetrahedron as binary little endian PLY, its lists of type `uchar int`.
    fn binary_tetrahedron() -> Vec<u8> {
        let mut bytes = binary_header("binary_little_endian", 4, "uchar int");
        for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]] {
            bytes.extend(p.iter().flat_map(|c| c.to_le_bytes()));
        }
        for face in [[0i32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
            bytes.push(3);
            bytes.extend(face.iter().flat_map(|v| v.to_le_bytes()));
        }
        bytes
    }

    fn parse(bytes: &[u8]) -> crate::error::Result<(Mesh, LoadReport)> {
        Mesh::parse_format(bytes, MeshFormat::Ply, &LoadOptions::default())
    }

    fn message(bytes: &[u8]) -> String {
        match parse(bytes).unwrap_err() {
            Error::MalformedMesh {
                format: "PLY",
                message,
                ..
            } => {
                assert!(
                    !message.contains('\n') && !message.contains('{'),
                    "one plain line: {message}"
                );
                message
            }
            other => panic!("expected a malformed PLY, got {other:?}"),
        }
    }

    #[test]
    fn ascii_and_binary_read_the_same_tetrahedron() {
        let (ascii, report) = parse(TETRAHEDRON.as_bytes()).unwrap();
        assert!(ascii.is_closed());
        assert_eq!((ascii.vertex_count(), ascii.face_count()), (4, 4));
        assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        let (binary, _) = parse(&binary_tetrahedron()).unwrap();
        assert_eq!(binary.positions(), ascii.positions());
        assert_eq!(binary.faces(), ascii.faces());
    }

    #[test]
    fn cr_and_crlf_line_ends_read_like_lf() {
        let (plain, _) = parse(TETRAHEDRON.as_bytes()).unwrap();
        for end in ["\r\n", "\r"] {
            let (mesh, _) = parse(TETRAHEDRON.replace('\n', end).as_bytes()).unwrap();
            assert_eq!(mesh.positions(), plain.positions(), "{end:?}");
            assert_eq!(mesh.faces(), plain.faces(), "{end:?}");
        }
        // A binary file whose header lines end in CR LF: the data starts after the last LF.
        let binary = binary_tetrahedron();
        let data = binary.len() - (4 * 12 + 4 * 13);
        let header = String::from_utf8(binary[..data].to_vec()).unwrap();
        let mut crlf = header.replace('\n', "\r\n").into_bytes();
        crlf.extend(&binary[data..]);
        assert_eq!(parse(&crlf).unwrap().0.faces(), plain.faces());
        // Line numbers count a CR LF pair once.
        let text = TETRAHEDRON
            .replace("1 0 0 0\n", "1 x 0 0\n")
            .replace('\n', "\r\n");
        assert_eq!(
            message(text.as_bytes()),
            "element 'vertex' 1 (line 16): property 'y': cannot read 'x' as a number"
        );
    }

    #[test]
    fn rows_beyond_the_declared_counts_are_an_error() {
        let extra = TETRAHEDRON.replace("0 1\n", "0 1\n2 3\n");
        assert_eq!(
            message(extra.as_bytes()),
            "line 24: unexpected '2 3' after the last element 'edge' (the header declares 1 of \
             them)"
        );
        // Eight face rows under `element face 4`: the fifth is where the edge should be.
        let faces: String = TETRAHEDRON
            .lines()
            .skip(18)
            .take(4)
            .map(|l| format!("{l}\n"))
            .collect();
        let doubled = TETRAHEDRON.replace("3 1 2 3\n", &format!("3 1 2 3\n{faces}"));
        assert_eq!(
            message(doubled.as_bytes()),
            "element 'edge' 0 (line 23): '2 1' after the values the header declares"
        );
        let mut binary = binary_tetrahedron();
        binary.extend([3, 0, 0, 0, 0]);
        assert_eq!(
            message(&binary),
            format!(
                "5 bytes from byte {} after the last element 'face' (the header declares 4 of \
                 them)",
                binary.len() - 5
            )
        );
        // Fewer rows than declared: the edge's row is read as the fifth face.
        let short = TETRAHEDRON.replace("element face 4", "element face 5");
        assert_eq!(
            message(short.as_bytes()),
            "element 'face' 4 (line 23): '1' after the values the header declares"
        );
        let cut: String = TETRAHEDRON
            .lines()
            .take(21)
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(
            message(cut.as_bytes()),
            "element 'face': the file ends after 3 of the 4 the header declares"
        );
    }

    #[test]
    fn header_errors_name_the_line() {
        for (text, expected) in [
            ("", "bad header: the file is empty (expected 'ply')"),
            ("PLY\n", "bad header: line 1: expected 'ply', found 'PLY'"),
            (
                "ply\nformat utf16 1.0\n",
                "bad header: line 2: unknown format 'utf16' (expected ascii, \
                 binary_little_endian or binary_big_endian)",
            ),
            (
                "ply\nformat ascii 1.0\nelement vertex -1\n",
                "bad header: line 3: the count of element 'vertex', '-1', is not a whole number \
                 ≥ 0",
            ),
            (
                "ply\nformat ascii 1.0\nproperty float x\n",
                "bad header: line 3: a property before any 'element' line",
            ),
            (
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\n",
                "bad header: line 4: unknown property type 'real'",
            ),
            (
                "ply\nformat ascii 1.0\nelement face 1\nproperty list float int v\n",
                "bad header: line 4: the length of list 'v' has the type 'float', not an \
                 integer type",
            ),
            (
                "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar vertex_indices\n",
                "bad header: line 4: expected 'property TYPE NAME' or 'property list \
                 COUNT_TYPE ITEM_TYPE NAME', found 'property list uchar vertex_indices'",
            ),
            (
                "ply\nformat ascii 1.0\nend_of_header\n",
                "bad header: line 3: unexpected header line 'end_of_header'",
            ),
            (
                "ply\nend_header\n",
                "bad header: line 2: 'end_header' before any 'format' line",
            ),
            (
                "ply\nformat ascii 1.0\n",
                "bad header: the file ends before the 'end_header' line",
            ),
        ] {
            assert_eq!(message(text.as_bytes()), expected, "{text:?}");
        }
    }

    #[test]
    fn counts_beyond_the_data_are_errors_not_allocations() {
        // A list length at the limit of its type, in ASCII and in binary.
        let ascii = TETRAHEDRON
            .replace("list uchar int", "list uint int")
            .replace("3 0 1 3\n", "4294967295 0 1 3\n");
        assert_eq!(
            message(ascii.as_bytes()),
            "element 'face' 1 (line 20): property 'vertex_indices': the list announces \
             4294967295 values but the line has 3 more"
        );
        let mut binary = binary_header("binary_big_endian", 1, "uint int");
        binary.extend([0u8; 48]);
        binary.extend(u32::MAX.to_be_bytes());
        binary.extend([0u8; 12]);
        assert_eq!(
            message(&binary),
            format!(
                "element 'face' 0 (byte {}): property 'vertex_indices': the list announces \
                 4294967295 values (17179869180 bytes) but the file has 12 bytes left",
                binary.len() - 16
            )
        );
        // Element counts at the limit of the platform's integers.
        let huge = TETRAHEDRON.replace("element face 4", "element face 18446744073709551615");
        assert!(
            message(huge.as_bytes()).starts_with("element 'face' 4 (line 23): "),
            "{}",
            message(huge.as_bytes())
        );
        let mut huge = binary_header("binary_little_endian", usize::MAX, "uchar int");
        let data_start = binary_header("binary_little_endian", 4, "uchar int").len();
        huge.extend(&binary_tetrahedron()[data_start..]);
        assert!(
            message(&huge).contains("element 'face'"),
            "{}",
            message(&huge)
        );
        // A value outside its type, a negative list length, a negative index.
        assert_eq!(
            message(TETRAHEDRON.replace("0 0 0 255", "0 0 0 256").as_bytes()),
            "element 'vertex' 0 (line 15): property 'red': 256 is outside the type's range \
             0..=255"
        );
        let signed = TETRAHEDRON
            .replace("list uchar int", "list char int")
            .replace("3 0 1 3\n", "-3 0 1 3\n");
        assert_eq!(
            message(signed.as_bytes()),
            "element 'face' 1 (line 20): property 'vertex_indices': list length -3"
        );
        assert_eq!(
            message(TETRAHEDRON.replace("3 0 1 3\n", "3 0 -1 3\n").as_bytes()),
            "face 1 refers to vertex -1"
        );
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        for end in 0..TETRAHEDRON.len() {
            if TETRAHEDRON[end..].trim().is_empty() {
                continue;
            }
            assert!(
                parse(&TETRAHEDRON.as_bytes()[..end]).is_err(),
                "prefix of {end} bytes parsed"
            );
        }
    }
}
