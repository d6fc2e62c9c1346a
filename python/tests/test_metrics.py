"""numpy → Mesh → build → metrics is the command line's `metrics --json` on the same mesh,
for every scheme: the same keys and the same numbers (not close: equal), the construction
time apart."""

from __future__ import annotations

import json
import math

import pytest

import smoothlab
from conftest import REPO, bumpy_grid, cli_metrics, deformed_icosahedron, run_cli, write_obj


def same(a, b) -> bool:
    """Equal values; NaN never occurs in the metrics (non-finite figures are errors)."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    return a == b


def compare(ours: dict, theirs: dict) -> list[str]:
    """The keys whose values differ (construct_ms is each run's own time)."""
    assert set(ours) == set(theirs), set(ours) ^ set(theirs)
    return [
        f"{k}: {ours[k]!r} != {theirs[k]!r}"
        for k in theirs
        if k != "construct_ms" and not same(ours[k], theirs[k])
    ]


@pytest.mark.parametrize("scheme", smoothlab.scheme_names())
def test_metrics_equal_the_cli_on_a_closed_mesh(tmp_path, scheme):
    v, f = deformed_icosahedron()
    mesh_file = write_obj(tmp_path / "ico.obj", v, f)
    [theirs] = cli_metrics(mesh_file, scheme, tmp_path / "m.json")
    surface = smoothlab.build(smoothlab.Mesh(v, f), scheme)
    ours = surface.metrics()
    assert list(ours) == list(theirs), "the JSON's keys in the JSON's order"
    assert compare(ours, theirs) == []
    for key in smoothlab.METRICS_CONTRACT_KEYS:
        assert key in ours
    assert ours["patches"] == len(surface) == surface.patch_count
    assert ours["construct_ms"] == surface.construct_ms > 0.0


def test_metrics_equal_the_cli_on_an_open_mesh_with_parameters(tmp_path):
    v, f = bumpy_grid()
    mesh_file = write_obj(tmp_path / "grid.obj", v, f)
    theirs = cli_metrics(mesh_file, "all", tmp_path / "m.json")
    measured = {m["scheme"] for m in theirs}
    closed_only = {s["name"] for s in smoothlab.schemes() if s["needs_closed_mesh"]}
    assert measured == set(smoothlab.scheme_names()) - closed_only
    mesh = smoothlab.Mesh(v, f)
    assert not mesh.is_closed
    for reference in theirs:
        surface = smoothlab.build(mesh, reference["scheme"])
        assert compare(surface.metrics(), reference) == [], reference["scheme"]
    # A parameter set from Python is the one set with --param.
    run_cli(
        "metrics", str(mesh_file), "--scheme", "hb", "--param", "beta=0.3", "--param", "plane=fourier",
        "--json", str(tmp_path / "p.json"),
    )
    [reference] = json.loads((tmp_path / "p.json").read_text())
    ours = smoothlab.build(mesh, "hb", beta=0.3, plane="fourier").metrics()
    assert ours["params"]["beta"] == "0.3" and ours["params"]["plane"] == "fourier"
    assert compare(ours, reference) == []


def test_a_mesh_file_loads_as_the_cli_loads_it(tmp_path):
    path = REPO / "scenes" / "octahedron.obj"
    [theirs] = cli_metrics(path, "loop94", tmp_path / "m.json")
    ours = smoothlab.build(smoothlab.load(path), "loop94").metrics()
    assert compare(ours, theirs) == []
