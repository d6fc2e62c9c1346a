"""`render` is `smoothlab render` for the same scene: the EXR's channels, one by one and bit
for bit; `save` writes what the command writes; two Python threads rendering at once give
the images of one at a time; Ctrl-C (KeyboardInterrupt) stops a render and leaves no file."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy as np
import pytest

import smoothlab
from conftest import bumpy_grid, deformed_icosahedron, run_cli, write_obj

OpenEXR = pytest.importorskip("OpenEXR")


def read_exr(path) -> dict[str, np.ndarray]:
    """Every channel of an EXR file by its name, read by the OpenEXR library."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        return {name: np.array(c.pixels) for name, c in exr.channels().items()}


SCENES = [
    # (mesh, scheme, CLI arguments, Python keyword arguments)
    ("ico", "hb", ["--mode", "zebra", "--size", "64x48", "--spp", "2"],
     dict(mode="zebra", size=(64, 48), spp=2)),
    ("ico", "nielson",
     ["--mode", "curvature", "--size", "40x30", "--curvature-quantity", "gaussian",
      "--eye", "3,1.5,4", "--target", "0.2,0,0", "--fov", "30"],
     dict(mode="curvature", size=(40, 30), quantity="gaussian",
          camera=dict(eye=[3, 1.5, 4], target=[0.2, 0, 0], fov=30))),
    ("grid", "pn", ["--mode", "isophote", "--size", "48x40", "--overlay", "faces"],
     dict(mode="isophote", size=(48, 40), overlay="faces")),
]


@pytest.mark.parametrize("mesh_name, scheme, cli_args, kwargs", SCENES)
def test_render_equals_the_cli_exr_channel_by_channel(tmp_path, mesh_name, scheme, cli_args, kwargs):
    v, f = deformed_icosahedron() if mesh_name == "ico" else bumpy_grid()
    mesh_file = write_obj(tmp_path / f"{mesh_name}.obj", v, f)
    run_cli("render", str(mesh_file), "--scheme", scheme, *cli_args, "-o", str(tmp_path / "cli"))
    theirs = read_exr(tmp_path / "cli.exr")
    surface = smoothlab.build(smoothlab.Mesh(v, f), scheme)
    image = smoothlab.render(surface, **kwargs)
    rgb, channels = image
    assert set(channels) == set(smoothlab.EXR_CHANNELS) | set(smoothlab.EXR_ID_CHANNELS)
    assert set(theirs) == set(channels)
    for name, plane in channels.items():
        assert plane.dtype == theirs[name].dtype and plane.shape == theirs[name].shape, name
        assert np.array_equal(plane, theirs[name]), f"channel {name} differs"
    w, h = kwargs["size"]
    assert rgb.shape == (h, w, 3) and rgb.dtype == np.float32
    assert np.array_equal(rgb, np.stack([theirs["R"], theirs["G"], theirs["B"]], axis=-1))
    assert image.stats["pixels"] == w * h
    assert image.stats["hits"] >= int((channels["id.patch"] != 2**32 - 1).sum()) > 0
    # save() writes the command's files: the same PNG bytes, the same EXR channels.
    written = image.save(tmp_path / "py.png")
    assert [os.path.basename(p) for p in written] == ["py.png", "py.exr"]
    # The same pixels (the files' text chunks differ: the command records its command line).
    Image = pytest.importorskip("PIL.Image")
    cli_png = np.asarray(Image.open(tmp_path / "cli.png").convert("RGB"))
    assert np.array_equal(np.asarray(Image.open(tmp_path / "py.png").convert("RGB")), cli_png)
    assert np.array_equal(image.srgb8, cli_png)
    again = read_exr(tmp_path / "py.exr")
    for name in theirs:
        assert np.array_equal(again[name], theirs[name]), name


def test_the_exr_geometry_is_the_surface_at_the_hit_parameters():
    v, f = deformed_icosahedron()
    surface = smoothlab.build(smoothlab.Mesh(v, f), "loop94")
    _, ch = smoothlab.render(surface, size=(48, 36), spp=1)
    hit = ch["id.patch"] != 2**32 - 1
    patches = ch["id.patch"][hit].astype(np.int64)
    uv = np.column_stack([ch["u"][hit], ch["v"][hit]]).astype(np.float64)
    got = surface.evaluate(patches, uv)
    p = np.column_stack([ch["P.X"][hit], ch["P.Y"][hit], ch["P.Z"][hit]])
    # u, v and P are stored as float32: agreement to float32 rounding of the scene's size.
    assert np.abs(got["position"] - p).max() <= 1e-5 * np.abs(v).max()
    assert np.array_equal(surface.faces[patches], ch["face_id"][hit].astype(np.int64))


def test_bad_scene_values_name_the_key():
    v, f = deformed_icosahedron()
    surface = smoothlab.build(smoothlab.Mesh(v, f), "pn")
    for kwargs, message in [
        (dict(mode="sparkle"), "sparkle"),
        (dict(duty=1.5), "zebra.duty"),
        (dict(strips=3), "strips"),
        (dict(size=(0, 10)), "render.size"),
        (dict(mode="normals", stripes=3), "mode 'normals' takes no parameters"),
        (dict(camera=dict(eye=[0, 0, float("nan")])), "eye"),
        (dict(scene={"mesh": "a.obj"}), "scene key 'mesh'"),
        (dict(scene={"render": {"turntable": 4}}), "render.turntable"),
        (dict(scene={"bvh": {"flatness": 5.0}}), "bvh.flatness"),
        (dict(exr_compression="lzw"), "lzw"),
    ]:
        with pytest.raises(smoothlab.SmoothlabError, match=message):
            smoothlab.render(surface, **kwargs)


def test_two_threads_rendering_at_once_give_the_images_of_one_at_a_time():
    v, f = deformed_icosahedron()
    mesh = smoothlab.Mesh(v, f)
    jobs = [
        (smoothlab.build(mesh, "hb"), dict(mode="zebra", size=(96, 72), spp=3)),
        (smoothlab.build(mesh, "gk"), dict(mode="curvature", size=(80, 60), spp=2)),
    ]
    alone = [smoothlab.render(s, **kw) for s, kw in jobs]
    together: list = [None, None]
    start = threading.Barrier(2)

    def work(k):
        start.wait()
        together[k] = smoothlab.render(jobs[k][0], **jobs[k][1])

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, together):
        assert np.array_equal(a.rgb, b.rgb)
        for name, plane in a.channels.items():
            assert np.array_equal(plane, b.channels[name]), name


def test_keyboard_interrupt_stops_a_render_and_leaves_no_file(tmp_path):
    v, f = deformed_icosahedron()
    surface = smoothlab.build(smoothlab.Mesh(v, f), "gk")
    big = dict(mode="shaded", size=(640, 480), spp=64)
    # A small render first, so that the timing below is the render's alone.
    smoothlab.render(surface, size=(16, 16))
    # Python answers SIGINT with KeyboardInterrupt only when it started with SIGINT at its
    # default; a process started in the background of a script inherits it ignored. The
    # handler a terminal user has is installed for this test alone.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            smoothlab.render(surface, output=tmp_path / "interrupted", **big)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    interrupted_after = time.monotonic() - started
    assert sorted(os.listdir(tmp_path)) == [], "no image and no temporary file"
    # The interrupt ended the render early: a whole one takes far longer than this.
    small = dict(big, size=(64, 48))
    t0 = time.monotonic()
    smoothlab.render(surface, output=tmp_path / "small", **small)
    per_pixel = (time.monotonic() - t0) / (64 * 48)
    assert interrupted_after < 0.25 * per_pixel * 640 * 480, (interrupted_after, per_pixel)
    assert sorted(os.listdir(tmp_path)) == ["small.exr", "small.png"]
