"""Meshes from numpy, polygon lists, trimesh and files; the load report and its warnings;
bad arrays raise clear exceptions (never a crash); unknown schemes and parameters raise
ValueError with the command line's message."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import smoothlab
from conftest import REPO, icosahedron, run_cli, write_obj


def test_a_clean_mesh_keeps_its_numbering_and_reports_nothing():
    v, f = icosahedron()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = smoothlab.Mesh(v, f)
    assert (mesh.vertex_count, mesh.face_count, mesh.edge_count) == (12, 20, 30)
    assert mesh.is_closed and mesh.euler_characteristic == 2
    assert np.array_equal(mesh.vertices, v)
    assert np.array_equal(mesh.faces, f)
    assert np.array_equal(mesh.input_faces, np.arange(20))
    assert mesh.report == {
        "welded": 0, "welded_near": 0, "weld_max_distance": 0.0, "reoriented_faces": 0,
        "sharp_edges": 0, "repairs": [], "warnings": [],
    }


def test_every_integer_type_and_nested_lists_are_accepted():
    v, f = icosahedron()
    reference = smoothlab.Mesh(v, f).faces
    for dtype in (np.int32, np.uint32, np.int16, np.uint64):
        assert np.array_equal(smoothlab.Mesh(v, f.astype(dtype)).faces, reference)
    assert np.array_equal(smoothlab.Mesh(v.tolist(), f.tolist()).faces, reference)


def test_repairs_are_reported_and_warned():
    v, f = icosahedron()
    flipped = f.copy()
    flipped[3] = flipped[3][[0, 2, 1]]
    with pytest.warns(smoothlab.SmoothlabWarning) as caught:
        mesh = smoothlab.Mesh(v, flipped)
    report = mesh.report
    assert report["reoriented_faces"] == 1
    assert [r["kind"] for r in report["repairs"]] == ["faces_reoriented"]
    assert report["repairs"][0]["count"] == 1
    assert [str(w.message) for w in caught] == report["warnings"]
    assert len(report["warnings"]) == 1
    with pytest.raises(smoothlab.SmoothlabError, match="--strict refuses"):
        smoothlab.Mesh(v, flipped, strict=True)


def test_polygons_are_split_as_a_file_is_read(tmp_path):
    cube_v = np.array([[i & 1, (i >> 1) & 1, i >> 2] for i in range(8)], dtype=np.float64)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    with pytest.warns(smoothlab.SmoothlabWarning, match="triangulated 6 faces"):
        from_array = smoothlab.Mesh(cube_v, np.array(quads))
    obj = tmp_path / "cube.obj"
    obj.write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in cube_v.tolist())
        + "".join("f " + " ".join(str(i + 1) for i in q) + "\n" for q in quads)
    )
    with pytest.warns(smoothlab.SmoothlabWarning, match="triangulated 6 faces"):
        from_file = smoothlab.load(obj)
    mixed = quads[:5] + [[1, 3, 7], [1, 7, 5]]
    with pytest.warns(smoothlab.SmoothlabWarning, match="triangulated 5 faces"):
        from_list = smoothlab.Mesh(cube_v, mixed)
    assert from_array.face_count == from_file.face_count == from_list.face_count == 12
    assert np.array_equal(from_array.faces, from_file.faces)
    assert np.array_equal(from_array.input_faces, from_file.input_faces)
    assert from_list.input_faces.max() == 6


def test_trimesh_meshes_convert_both_ways():
    trimesh = pytest.importorskip("trimesh")
    v, f = icosahedron()
    tm = trimesh.Trimesh(vertices=v, faces=f, process=False)
    for mesh in (smoothlab.Mesh(tm), smoothlab.from_trimesh(tm)):
        assert np.array_equal(mesh.faces, f) and np.array_equal(mesh.vertices, v)
    back = smoothlab.to_trimesh(smoothlab.Mesh(tm))
    assert np.array_equal(back.faces, f) and back.is_watertight


def test_files_of_every_format_load():
    mesh = smoothlab.load(REPO / "scenes" / "octahedron.obj")
    assert (mesh.vertex_count, mesh.face_count) == (6, 8)
    with pytest.raises(OSError, match="nothing.obj"):
        smoothlab.load(REPO / "nothing.obj")
    with pytest.raises(smoothlab.SmoothlabError, match="unknown mesh format"):
        smoothlab.load(REPO / "Cargo.toml")


@pytest.mark.parametrize(
    "vertices, faces, error, message",
    [
        (np.zeros((12, 2)), None, ValueError, r"vertices must have shape \(n, 3\), got shape \(12, 2\)"),
        (np.zeros(36), None, ValueError, r"vertices must have shape \(n, 3\)"),
        ("nan", None, ValueError, r"vertices: vertex 4 has a non-finite value \(column 1: NaN\)"),
        ("inf", None, ValueError, r"vertex 4 has a non-finite value \(column 1: inf\)"),
        ("strided", None, ValueError, "C-contiguous"),
        ("fortran", None, ValueError, "C-contiguous"),
        ("float32", None, TypeError, "vertices must be a float64 array, got dtype float32"),
        (None, "float faces", TypeError, "faces must be an integer array"),
        (None, "strided faces", ValueError, "faces must be C-contiguous"),
        (None, "negative", ValueError, "face 2 corner 1 refers to vertex -1"),
        (None, "too large", smoothlab.SmoothlabError, "face 2 refers to vertex 12, but the mesh has only 12 vertices"),
        (None, "huge", ValueError, "face 2 corner 1 refers to vertex 4294967296"),
        (None, "pairs", smoothlab.SmoothlabError, "face 0 has 2 corners"),
        (None, "empty", smoothlab.SmoothlabError, "empty"),
        (None, "ragged strings", TypeError, "face 1 corner 0 is not an integer"),
    ],
)
def test_bad_arrays_raise_clear_exceptions(vertices, faces, error, message):
    v, f = icosahedron()
    if isinstance(vertices, str):
        kind, vertices = vertices, v.copy()
        if kind == "nan":
            vertices[4, 1] = np.nan
        elif kind == "inf":
            vertices[4, 1] = np.inf
        elif kind == "strided":
            vertices = np.repeat(v, 2, axis=1)[:, ::2]
        elif kind == "fortran":
            vertices = np.asfortranarray(v)
        elif kind == "float32":
            vertices = v.astype(np.float32)
    elif vertices is None:
        vertices = v
    if faces is None:
        faces = f
    else:
        kind, faces = faces, f.copy()
        if kind == "float faces":
            faces = f.astype(np.float64)
        elif kind == "strided faces":
            faces = np.repeat(f, 2, axis=1)[:, ::2]
        elif kind == "negative":
            faces[2, 1] = -1
        elif kind == "too large":
            faces[2, 1] = 12
        elif kind == "huge":
            faces[2, 1] = 2**32
        elif kind == "pairs":
            faces = f[:, :2].copy()
        elif kind == "empty":
            faces = np.zeros((0, 3), dtype=np.int64)
        elif kind == "ragged strings":
            faces = [[0, 1, 2], ["a", 1, 2]]
    with pytest.raises(error, match=message):
        smoothlab.Mesh(vertices, faces)


def test_bad_load_options_name_the_option():
    v, f = icosahedron()
    with pytest.raises(smoothlab.SmoothlabError, match="weld_tolerance: "):
        smoothlab.Mesh(v, f, weld_tolerance=2.0)
    with pytest.raises(smoothlab.SmoothlabError, match="crease_angle: "):
        smoothlab.Mesh(v, f, crease_angle=200.0)
    with pytest.raises(TypeError, match="faces missing"):
        smoothlab.Mesh(v)


def test_unknown_schemes_and_parameters_raise_the_cli_message(tmp_path):
    v, f = icosahedron()
    mesh_file = write_obj(tmp_path / "ico.obj", v, f)
    mesh = smoothlab.Mesh(v, f)
    for args, kwargs in [
        (["--scheme", "nope"], {"scheme": "nope"}),
        (["--scheme", "hb", "--param", "bogus=1"], {"scheme": "hb", "bogus": 1}),
        (["--scheme", "pn", "--param", "normals=sideways"], {"scheme": "pn", "normals": "sideways"}),
    ]:
        done = run_cli("metrics", str(mesh_file), *args, check=False)
        assert done.returncode != 0
        line = done.stderr.strip().splitlines()[-1]
        assert line.startswith("error: "), done.stderr
        with pytest.raises(ValueError) as caught:
            smoothlab.build(mesh, kwargs.pop("scheme"), **kwargs)
        assert isinstance(caught.value, smoothlab.SmoothlabError)
        assert str(caught.value) == line[len("error: "):]


def test_schemes_list_the_registry():
    listed = smoothlab.schemes()
    names = [s["name"] for s in listed]
    assert names[:3] == ["flat", "pn", "hb"] and len(names) == len(set(names)) >= 8
    done = run_cli("schemes")
    for s in listed:
        assert f"{s['name']}: {s['summary']}" in done.stdout
        for p in s["params"]:
            assert f"    {p['name']}={p['default']}  {p['help']}" in done.stdout
