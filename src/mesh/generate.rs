//! Generated test meshes (the files in scenes/ are written from these): platonic solids, a
//! deformed icosahedron, a triangulated cube, meshes with chosen vertex valences, a torus and a
//! genus-2 surface.
