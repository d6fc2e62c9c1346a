"""`Surface.evaluate` agrees with the exported control points, evaluated here by an
independent de Casteljau (and its derivative nets for normals and curvatures); the patch
arrays are the export's; `evaluate_face` finds the patch of a face point."""

from __future__ import annotations

import json

import numpy as np
import pytest

import smoothlab
from conftest import deformed_icosahedron


def multi_indices(d: int) -> list[tuple[int, int, int]]:
    """The export's point order: i from d down to 0, then j from d−i down to 0."""
    return [(i, j, d - i - j) for i in range(d, -1, -1) for j in range(d - i, -1, -1)]


def casteljau(net: dict, d: int, b: np.ndarray) -> np.ndarray:
    """The degree-d net at barycentric b = (1−u−v, u, v), by repeated convex combination."""
    level = dict(net)
    for r in range(d, 0, -1):
        level = {
            (i, j, r - 1 - i - j): b[0] * level[(i + 1, j, r - 1 - i - j)]
            + b[1] * level[(i, j + 1, r - 1 - i - j)]
            + b[2] * level[(i, j, r - i - j)]
            for i in range(r)
            for j in range(r - i)
        }
    return level[(0, 0, 0)]


def derivative(net: dict, d: int, toward: int) -> dict:
    """The net of ∂/∂u (toward 1) or ∂/∂v (toward 2) with u = b1, v = b2, b0 = 1 − u − v:
    degree d − 1, points d (b_{I+e_toward} − b_{I+e_0})."""
    e = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    out = {}
    for i, j, k in multi_indices(d - 1):
        up = (i + e[toward][0], j + e[toward][1], k + e[toward][2])
        out[(i, j, k)] = d * (net[up] - net[(i + 1, j, k)])
    return out


def reference_jet(points: np.ndarray, d: int, u: float, v: float):
    net = dict(zip(multi_indices(d), points))
    b = np.array([1.0 - u - v, u, v])
    su, sv = derivative(net, d, 1), derivative(net, d, 2)
    p = casteljau(net, d, b)
    du, dv = casteljau(su, d - 1, b), casteljau(sv, d - 1, b)
    if d >= 2:
        duu = casteljau(derivative(su, d - 1, 1), d - 2, b)
        duv = casteljau(derivative(su, d - 1, 2), d - 2, b)
        dvv = casteljau(derivative(sv, d - 1, 2), d - 2, b)
    else:
        duu = duv = dvv = np.zeros(3)
    n = np.cross(du, dv)
    n /= np.linalg.norm(n)
    E, F, G = du @ du, du @ dv, dv @ dv
    L, M, N = duu @ n, duv @ n, dvv @ n
    K = (L * N - M * M) / (E * G - F * F)
    H = (E * N - 2 * F * M + G * L) / (2 * (E * G - F * F))
    disc = max(H * H - K, 0.0) ** 0.5
    return p, n, H + disc, H - disc, K, H


def points_on_the_triangle(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    uv = rng.random((count, 2))
    outside = uv.sum(axis=1) > 1.0
    uv[outside] = 1.0 - uv[outside]
    return np.vstack([uv, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.5]]])


@pytest.mark.parametrize("scheme", smoothlab.scheme_names())
def test_evaluate_agrees_with_the_exported_control_points(tmp_path, scheme):
    v, f = deformed_icosahedron()
    surface = smoothlab.build(smoothlab.Mesh(v, f), scheme)
    path = tmp_path / "patches.json"
    surface.export(path)
    exported = json.loads(path.read_text())
    assert exported["scheme"] == scheme
    assert len(exported["patches"]) == len(surface)
    assert np.array_equal(surface.faces, [p["face"] for p in exported["patches"]])
    assert np.array_equal(surface.pieces, [p["piece"] for p in exported["patches"]])
    assert np.array_equal(surface.degrees, [p["degree"] for p in exported["patches"]])
    diag = np.linalg.norm(v.max(axis=0) - v.min(axis=0))
    uv = points_on_the_triangle(12, seed=len(scheme))
    checked = 0
    for index, record in enumerate(exported["patches"]):
        points = np.array(record["points"])
        ours = surface.control_points(index)
        # The export writes the shortest text that reads back to the same float64.
        assert np.array_equal(ours.reshape(-1, 3), points), index
        if record.get("kind") == "blend":
            assert surface.kind(index) == "blend" and ours.shape == (3, len(points) // 3, 3)
            continue
        assert surface.kind(index) == "bezier"
        d = record["degree"]
        got = surface.evaluate(index, uv)
        bary = np.column_stack([1.0 - uv.sum(axis=1), uv])
        again = surface.evaluate(np.full(len(uv), index), bary)
        for key in got:
            assert np.array_equal(got[key], again[key], equal_nan=True), key
        for k, (u, w) in enumerate(uv):
            p, n, k1, k2, K, H = reference_jet(points, d, u, w)
            assert np.abs(got["position"][k] - p).max() <= 1e-14 * diag * d
            assert np.abs(got["normal"][k] - n).max() <= 1e-12, (index, k)
            scale = max(abs(k1), abs(k2), 1.0 / diag)
            for key, value in (("k1", k1), ("k2", k2), ("H", H)):
                assert abs(got[key][k] - value) <= 1e-9 * scale, (key, index, k)
            assert abs(got["K"][k] - K) <= 1e-9 * scale * scale, (index, k)
        checked += 1
    kinds = {surface.kind(i) for i in range(len(surface))}
    assert checked > 0 or kinds == {"blend"}


def test_evaluate_face_finds_the_patch_of_a_face_point():
    v, f = deformed_icosahedron()
    surface = smoothlab.build(smoothlab.Mesh(v, f), "hb")  # several patches per face
    rng = np.random.default_rng(7)
    for face in (0, 7, 19):
        bary = rng.dirichlet([1.0, 1.0, 1.0], size=40)
        got = surface.evaluate_face(face, bary)
        assert set(surface.faces[got["patch"]]) == {face}
        again = surface.evaluate(got["patch"], got["uv"])
        assert np.array_equal(got["position"], again["position"])
        for k in range(len(bary)):
            domain = surface.domain(int(got["patch"][k]))
            u, w = got["uv"][k]
            back = np.array([1.0 - u - w, u, w]) @ domain
            assert np.abs(back - bary[k]).max() <= 1e-14
    assert len(set(surface.evaluate_face(0, rng.dirichlet([1, 1, 1], 200))["patch"])) > 1


def test_bad_parameter_points_raise_clear_exceptions():
    v, f = deformed_icosahedron()
    surface = smoothlab.build(smoothlab.Mesh(v, f), "pn")
    with pytest.raises(IndexError, match="patch 20 does not exist"):
        surface.evaluate(20, [[0.2, 0.2]])
    with pytest.raises(IndexError, match=r"patch\[1\] = -1 is not a patch index"):
        surface.evaluate(np.array([0, -1]), [[0.2, 0.2], [0.1, 0.1]])
    with pytest.raises(ValueError, match="patch has 2 indices but uv 1 points"):
        surface.evaluate(np.array([0, 1]), [[0.2, 0.2]])
    with pytest.raises(ValueError, match="non-finite"):
        surface.evaluate(0, [[0.2, np.nan]])
    with pytest.raises(ValueError, match="sum is"):
        surface.evaluate(0, [[0.5, 0.2, 0.2]])
    with pytest.raises(ValueError, match=r"shape \(n, 2\)"):
        surface.evaluate(0, np.zeros((3, 4)))
    with pytest.raises(ValueError, match="C-contiguous"):
        surface.evaluate(0, np.zeros((3, 4))[:, ::2])
    with pytest.raises(ValueError, match="not a point of the face"):
        surface.evaluate_face(0, [[1.5, -0.25, -0.25]])
    with pytest.raises(IndexError, match="face 20 does not exist"):
        surface.evaluate_face(20, [[1.0, 0.0, 0.0]])
