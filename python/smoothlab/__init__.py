"""smoothlab: smooth surfaces from triangle meshes, measured and ray-traced exactly.

The classical schemes of the literature (flat, PN triangles, Hahmann–Bonneau HB00, Loop94,
Piper87, Nielson's side-vertex and Fang–Mann blends, G^k splines) built on a mesh from numpy
arrays or a file, their patches and exact evaluation as numpy arrays, the metrics of
``smoothlab metrics --json`` as a dict, exports, and the exact ray tracer's images with
their EXR channels — the same library as the ``smoothlab`` command line, the same numbers.

>>> import numpy as np, smoothlab
>>> mesh = smoothlab.load("scenes/octahedron.obj")           # doctest: +SKIP
>>> surface = smoothlab.build(mesh, "hb")                    # doctest: +SKIP
>>> surface.metrics()["g1_max_rad"]                          # doctest: +SKIP
>>> rgb, channels = smoothlab.render(surface, "zebra", size=(320, 240))  # doctest: +SKIP

See docs/python.md for the whole interface.
"""

from __future__ import annotations

from typing import Any

from ._smoothlab import (
    EXR_CHANNELS,
    EXR_ID_CHANNELS,
    METRICS_CONTRACT_KEYS,
    Mesh,
    Render,
    SmoothlabError,
    SmoothlabWarning,
    Surface,
    __version__,
    build,
    load,
    render,
    schemes,
)

__all__ = [
    "EXR_CHANNELS",
    "EXR_ID_CHANNELS",
    "METRICS_CONTRACT_KEYS",
    "Mesh",
    "Render",
    "SmoothlabError",
    "SmoothlabWarning",
    "Surface",
    "__version__",
    "build",
    "from_trimesh",
    "load",
    "metrics_table",
    "render",
    "scheme_names",
    "schemes",
    "to_trimesh",
]


def scheme_names() -> list[str]:
    """The registered scheme names, in the registry's order."""
    return [s["name"] for s in schemes()]


def from_trimesh(mesh: Any, **options: Any) -> Mesh:
    """A :class:`Mesh` from a ``trimesh.Trimesh`` (its ``vertices`` and ``faces``); the
    keyword arguments are :class:`Mesh`'s load options. trimesh itself is not needed to call
    this, only an object with those two arrays."""
    return Mesh(mesh.vertices, mesh.faces, **options)


def to_trimesh(mesh: Mesh) -> Any:
    """The loaded (welded, oriented) mesh as a ``trimesh.Trimesh``; needs trimesh
    (``pip install trimesh``)."""
    try:
        import trimesh
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("to_trimesh needs trimesh: pip install trimesh") from e
    return trimesh.Trimesh(vertices=mesh.vertices, faces=mesh.faces, process=False)


def metrics_table(surfaces: list[Surface]) -> Any:
    """The metrics of ``surfaces`` as a ``pandas.DataFrame`` indexed by scheme (pandas
    needed); list and dict values (``params``, ``repairs``) stay objects."""
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("metrics_table needs pandas: pip install pandas") from e
    rows = [s.metrics() for s in surfaces]
    return pandas.DataFrame(rows).set_index("scheme")
