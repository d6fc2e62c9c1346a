//! Small writers of mesh files (PLY ASCII and binary, OFF, STL ASCII and binary) for tests
//! that read a mesh back in another format.

use glam::DVec3;

/// PLY byte order of a binary file.
#[derive(Clone, Copy, Debug)]
pub enum Endian {
    /// `binary_little_endian`.
    Little,
    /// `binary_big_endian`.
    Big,
}

/// The PLY header: double coordinates, one skipped `confidence` property per vertex, int
/// indices with a uchar count.
fn ply_header(format: &str, vertices: usize, faces: usize) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment written by a test\nelement vertex {vertices}\n\
         property double x\nproperty double y\nproperty double z\nproperty float confidence\n\
         element face {faces}\nproperty list uchar int vertex_indices\nend_header\n"
    )
}

/// An ASCII PLY file; coordinates in shortest round-trip form, so reading gives them back
/// exactly.
pub fn ply_ascii(positions: &[DVec3], faces: &[Vec<u32>]) -> Vec<u8> {
    let mut text = ply_header("ascii", positions.len(), faces.len());
    for p in positions {
        text += &format!("{} {} {} 1\n", p.x, p.y, p.z);
    }
    for face in faces {
        let corners: Vec<String> = face.iter().map(|v| v.to_string()).collect();
        text += &format!("{} {}\n", face.len(), corners.join(" "));
    }
    text.into_bytes()
}

/// A binary PLY file of the given byte order.
pub fn ply_binary(positions: &[DVec3], faces: &[Vec<u32>], endian: Endian) -> Vec<u8> {
    let format = match endian {
        Endian::Little => "binary_little_endian",
        Endian::Big => "binary_big_endian",
    };
    let mut bytes = ply_header(format, positions.len(), faces.len()).into_bytes();
    let f64_bytes = |v: f64| match endian {
        Endian::Little => v.to_le_bytes(),
        Endian::Big => v.to_be_bytes(),
    };
    let f32_bytes = |v: f32| match endian {
        Endian::Little => v.to_le_bytes(),
        Endian::Big => v.to_be_bytes(),
    };
    let i32_bytes = |v: i32| match endian {
        Endian::Little => v.to_le_bytes(),
        Endian::Big => v.to_be_bytes(),
    };
    for p in positions {
        for c in p.to_array() {
            bytes.extend(f64_bytes(c));
        }
        bytes.extend(f32_bytes(1.0));
    }
    for face in faces {
        bytes.push(face.len() as u8);
        for &v in face {
            bytes.extend(i32_bytes(v as i32));
        }
    }
    bytes
}

/// An OFF file; coordinates in shortest round-trip form.
pub fn off(positions: &[DVec3], faces: &[Vec<u32>]) -> Vec<u8> {
    let mut text = format!("OFF\n{} {} 0\n", positions.len(), faces.len());
    for p in positions {
        text += &format!("{} {} {}\n", p.x, p.y, p.z);
    }
    for face in faces {
        let corners: Vec<String> = face.iter().map(|v| v.to_string()).collect();
        text += &format!("{} {}\n", face.len(), corners.join(" "));
    }
    text.into_bytes()
}

/// An ASCII STL file: one facet per triangle, coordinates rounded to f32 (as STL stores
/// them) and written in shortest round-trip form for f32.
pub fn stl_ascii(positions: &[DVec3], faces: &[[u32; 3]]) -> Vec<u8> {
    let mut text = String::from("solid test\n");
    for face in faces {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for &v in face {
            let p = positions[v as usize].as_vec3();
            text += &format!("      vertex {} {} {}\n", p.x, p.y, p.z);
        }
        text += "    endloop\n  endfacet\n";
    }
    text += "endsolid test\n";
    text.into_bytes()
}

/// A binary STL file; its 80-byte header starts with `header` (padded with spaces).
pub fn stl_binary(positions: &[DVec3], faces: &[[u32; 3]], header: &str) -> Vec<u8> {
    let mut bytes = format!("{header:<80}").into_bytes();
    bytes.truncate(80);
    bytes.extend((faces.len() as u32).to_le_bytes());
    for face in faces {
        bytes.extend([0u8; 12]);
        for &v in face {
            for c in positions[v as usize].as_vec3().to_array() {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

/// `positions` rounded to single precision, as an STL file stores them.
pub fn rounded_to_f32(positions: &[DVec3]) -> Vec<DVec3> {
    positions.iter().map(|p| p.as_vec3().as_dvec3()).collect()
}

/// Triangles as polygons.
pub fn polygons(faces: &[[u32; 3]]) -> Vec<Vec<u32>> {
    faces.iter().map(|f| f.to_vec()).collect()
}
