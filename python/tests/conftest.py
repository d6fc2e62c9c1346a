"""Shared fixtures: the repository, the smoothlab command line (the reference the package is
compared with), and meshes made here with numpy."""

from __future__ import annotations

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def cli_path() -> pathlib.Path:
    """The smoothlab binary: $SMOOTHLAB_BIN, else the release build of this repository."""
    given = os.environ.get("SMOOTHLAB_BIN")
    path = pathlib.Path(given) if given else REPO / "target" / "release" / "smoothlab"
    if not path.is_file():
        pytest.fail(
            f"the smoothlab command line is needed as the reference: {path} does not exist "
            "(run `cargo build --release` in the repository or set SMOOTHLAB_BIN)"
        )
    return path


def run_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the command line with `args`; with `check`, a failure fails the test with its
    standard error."""
    done = subprocess.run(
        [str(cli_path()), *args], capture_output=True, text=True, timeout=600
    )
    if check and done.returncode != 0:
        pytest.fail(f"smoothlab {' '.join(args)} failed: {done.stderr}")
    return done


def icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """The regular icosahedron (12 vertices, 20 outward faces)."""
    t = (1.0 + 5.0**0.5) / 2.0
    v = np.array(
        [
            [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
            [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
            [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
        ],
        dtype=np.float64,
    )
    f = np.array(
        [
            [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
            [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
            [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
            [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
        ],
        dtype=np.int64,
    )
    return v, f


def deformed_icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """The icosahedron with every vertex moved by a fixed, irregular amount (no symmetry left
    for a scheme to hide behind)."""
    v, f = icosahedron()
    k = np.arange(12, dtype=np.float64)
    scale = 1.0 + 0.15 * np.sin(1.7 * k + 0.3) + 0.05 * np.cos(3.1 * k)
    return v * scale[:, None] + np.array([0.3, -0.2, 0.1]), f


def bumpy_grid(n: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """An open n×n grid of squares over a bump, each square cut into two triangles."""
    xs = np.linspace(-1.0, 1.0, n + 1)
    x, y = np.meshgrid(xs, xs)
    z = 0.4 * np.exp(-2.0 * (x**2 + y**2)) + 0.05 * x * y
    v = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 1, a + n + 2
            faces += [[a, b, d], [a, d, c]]
    return v, np.array(faces, dtype=np.int64)


def write_obj(path: pathlib.Path, v: np.ndarray, f: np.ndarray) -> pathlib.Path:
    """Writes an OBJ whose coordinates read back to exactly the same float64 (repr)."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()]
    lines += ["f " + " ".join(str(i + 1) for i in face) for face in f.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def cli_metrics(mesh_file: pathlib.Path, scheme: str, out: pathlib.Path) -> list[dict]:
    """The command line's metrics JSON of `scheme` (or all) on `mesh_file`."""
    run_cli("metrics", str(mesh_file), "--scheme", scheme, "--json", str(out))
    return json.loads(out.read_text())


@pytest.fixture
def ico_file(tmp_path: pathlib.Path) -> pathlib.Path:
    return write_obj(tmp_path / "ico.obj", *deformed_icosahedron())
