//! Triangle meshes: OBJ input, welding, validation with typed errors, half-edge topology,
//! ordered one-rings and vertex normals. Every scheme reads its input through [`Mesh`].

pub mod generate;

use std::path::Path;

use glam::DVec3;

use crate::error::Result;
use crate::geom::Aabb;

/// Where vertex normals come from (`--param normals=estimate|obj`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NormalSource {
    /// Angle-weighted average of the incident face normals.
    #[default]
    Estimate,
    /// The normals stored in the OBJ file (error if there are none or they disagree per vertex).
    Obj,
}

/// What loading did to the input besides parsing: welded vertices, re-oriented faces, warnings.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadReport {
    /// Vertices merged into an earlier vertex with the identical position.
    pub welded: usize,
    /// Faces whose orientation was flipped to agree with their neighbours.
    pub reoriented_faces: usize,
    /// Human-readable warnings (one line each).
    pub warnings: Vec<String>,
}

/// One undirected mesh edge with its one or two faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshEdge {
    /// Smaller vertex index.
    pub a: u32,
    /// Larger vertex index.
    pub b: u32,
    /// The face on one side, and the face on the other (None on a boundary edge).
    pub faces: (u32, Option<u32>),
}

/// A validated, consistently oriented, manifold triangle mesh with its topology.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    obj_normals: Option<Vec<DVec3>>,
}

impl Mesh {
    /// Builds and validates a mesh (weld, checks, orientation, topology).
    pub fn from_triangles(
        positions: Vec<DVec3>,
        faces: Vec<[u32; 3]>,
    ) -> Result<(Mesh, LoadReport)> {
        todo!()
    }
    /// Loads an OBJ file (position indices only; normals kept per position when consistent).
    pub fn load_obj(path: &Path) -> Result<(Mesh, LoadReport)> {
        todo!()
    }
    /// Parses OBJ text (for embedded meshes and tests).
    pub fn parse_obj(text: &str) -> Result<(Mesh, LoadReport)> {
        todo!()
    }
    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Faces as counter-clockwise vertex triples (consistently oriented).
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.faces
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }
    /// Number of edges at vertex `v`.
    pub fn valence(&self, v: u32) -> usize {
        todo!()
    }
    /// Neighbours of `v` ordered so that `(v, ring[j], ring[j+1])` is a face (indices mod n
    /// for an interior vertex; for a boundary vertex the fan starts and ends at the boundary).
    pub fn one_ring(&self, v: u32) -> &[u32] {
        todo!()
    }
    /// `ring_faces(v)[j]` is the face `(v, one_ring(v)[j], one_ring(v)[j+1])`.
    pub fn ring_faces(&self, v: u32) -> &[u32] {
        todo!()
    }
    /// True if `v` lies on a boundary edge.
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        todo!()
    }
    /// True if no edge is a boundary edge.
    pub fn is_closed(&self) -> bool {
        todo!()
    }
    /// The first boundary edge, if any (for "needs a closed mesh" errors).
    pub fn first_boundary_edge(&self) -> Option<(u32, u32)> {
        todo!()
    }
    /// The face across edge `e` of face `f` (edge e runs from `faces[f][e]` to
    /// `faces[f][(e+1)%3]`) and that edge's index in the neighbour; None on a boundary.
    pub fn neighbor(&self, f: u32, e: usize) -> Option<(u32, usize)> {
        todo!()
    }
    /// All undirected edges, each once.
    pub fn edges(&self) -> Vec<MeshEdge> {
        todo!()
    }
    /// One unit normal per vertex.
    pub fn vertex_normals(&self, source: NormalSource) -> Result<Vec<DVec3>> {
        todo!()
    }
    /// Bounding box of the vertices.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.positions)
    }
}
