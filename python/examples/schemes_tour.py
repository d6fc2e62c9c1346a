"""Every scheme on one mesh: build, measure, tabulate, and look at the zebra stripes.

    python python/examples/schemes_tour.py [MESH] [--out DIR]

Without MESH, a deformed icosahedron made here with numpy is used. The metrics table is a
pandas DataFrame when pandas is installed (plain text otherwise); the zebra image of every
scheme is shown in one matplotlib figure, saved as DIR/zebra.png, when matplotlib is
installed (the renders' own PNGs are written to DIR either way).
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile
import warnings

import numpy as np

import smoothlab


def deformed_icosahedron() -> smoothlab.Mesh:
    t = (1.0 + 5.0**0.5) / 2.0
    v = np.array(
        [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]],
        dtype=np.float64,
    )
    f = np.array(
        [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    )
    k = np.arange(12.0)
    return smoothlab.Mesh(v * (1.0 + 0.15 * np.sin(1.7 * k + 0.3))[:, None], f)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", nargs="?", help="OBJ, PLY, OFF or STL file")
    parser.add_argument("--out", default=None, help="folder for the images")
    parser.add_argument("--size", default="240x180", help="image size WxH")
    args = parser.parse_args()
    out = pathlib.Path(args.out or tempfile.mkdtemp(prefix="smoothlab-tour-"))
    w, h = (int(x) for x in args.size.split("x"))

    mesh = smoothlab.load(args.mesh) if args.mesh else deformed_icosahedron()
    print(mesh)
    surfaces = []
    for spec in smoothlab.schemes():
        if spec["needs_closed_mesh"] and not mesh.is_closed:
            print(f"skipped {spec['name']}: it needs a closed mesh")
            continue
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            surfaces.append(smoothlab.build(mesh, spec["name"]))
        for w_ in caught:
            print(f"warning: {w_.message}")

    columns = ["patches", "g0_max_rel", "g1_max_rad", "curvature_jump_max_rel",
               "continuity_order", "min_regularity_rel", "construct_ms"]
    try:
        table = smoothlab.metrics_table(surfaces)[columns]
        print(table.to_string(float_format=lambda x: f"{x:.2e}"))
    except ImportError:
        print("scheme      " + "  ".join(f"{c:>12}" for c in columns))
        for s in surfaces:
            m = s.metrics()
            cells = ("-" if m[c] is None else f"{m[c]:.3g}" for c in columns)
            print(f"{s.scheme:<12}" + "  ".join(f"{c:>12}" for c in cells))

    images = []
    for s in surfaces:
        image = smoothlab.render(s, "zebra", size=(w, h), spp=2,
                                 output=out / f"{s.scheme}-zebra")
        images.append((s.scheme, image))
    print(f"wrote {len(images)} zebra renders to {out}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    cols = 4
    rows = (len(images) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3 * cols, 2.4 * rows))
    for ax in np.ravel(axes):
        ax.axis("off")
    for ax, (name, image) in zip(np.ravel(axes), images):
        ax.imshow(image.srgb8)
        ax.set_title(name)
    fig.tight_layout()
    fig.savefig(out / "zebra.png", dpi=100)
    print(f"wrote {out / 'zebra.png'}")


if __name__ == "__main__":
    main()
