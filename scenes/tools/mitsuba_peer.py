#!/usr/bin/env python3
"""Path-trace smoothlab's shaded scene with Mitsuba 3 for an equal-time noise comparison.

The surface is a fine tessellation of the patches (`smoothlab export --format obj --tess N`),
the light a lat-long EXR (`cargo run --release --example studio_map -- studio.exr` writes the
built-in studio; smoothlab reads the same file with `[shaded] environment = "studio.exr"`), the
material Mitsuba's `roughplastic` (GGX, index 1.5) over the same diffuse base colour, and the
integrator Mitsuba's `path` with the same longest path (smoothlab's `bounces` + 1 = Mitsuba's
`max_depth`). smoothlab's lat-long convention (u = 1/2 + atan2(x, -z) / 2pi) is Mitsuba's
rotated by 180 degrees about +Y, so the emitter carries that rotation.

usage:
  mitsuba_peer.py MESH.obj ENV.exr EYE TARGET UP FOV WxH OUT.exr (--spp N | --seconds T)
                  [--variant llvm_ad_rgb] [--sampler multijitter] [--base R,G,B]
                  [--alpha 0.026] [--max-depth 7] [--seed 0]
EYE/TARGET/UP as x,y,z; FOV vertical, degrees. With --seconds the sample count is chosen so the
render takes about T seconds of wall time: a warm-up render (JIT compilation for the LLVM
variants) and a timed calibration render at a few samples per pixel come first. Prints the spp
and the wall time of the final render.
Needs: python3 -m venv /tmp/mitsuba-venv && /tmp/mitsuba-venv/bin/pip install mitsuba numpy
"""
import argparse
import time

import mitsuba as mi

ap = argparse.ArgumentParser()
for name in ["mesh", "env", "eye", "target", "up", "fov", "size", "out"]:
    ap.add_argument(name)
ap.add_argument("--spp", type=int)
ap.add_argument("--seconds", type=float)
ap.add_argument("--variant", default="llvm_ad_rgb")
ap.add_argument("--sampler", default="multijitter")
ap.add_argument("--base", default="0.55,0.12,0.08")
ap.add_argument("--alpha", type=float, default=0.026)
ap.add_argument("--max-depth", type=int, default=7)
ap.add_argument("--rr-depth", type=int, default=4)
ap.add_argument("--seed", type=int, default=0)
a = ap.parse_args()
if (a.spp is None) == (a.seconds is None):
    ap.error("give exactly one of --spp and --seconds")

mi.set_variant(a.variant)
vec = lambda s: [float(x) for x in s.split(",")]
w, h = (int(x) for x in a.size.split("x"))


def scene(spp):
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": a.max_depth, "rr_depth": a.rr_depth},
        "sensor": {
            "type": "perspective", "fov": float(a.fov), "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=vec(a.eye), target=vec(a.target), up=vec(a.up)),
            "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"}},
            "sampler": {"type": a.sampler, "sample_count": spp},
        },
        "surface": {
            "type": "obj", "filename": a.mesh, "face_normals": False,
            "bsdf": {
                "type": "roughplastic", "distribution": "ggx", "alpha": a.alpha,
                "int_ior": 1.5, "ext_ior": 1.0,
                "diffuse_reflectance": {"type": "rgb", "value": vec(a.base)},
            },
        },
        "light": {
            "type": "envmap", "filename": a.env,
            "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 180),
        },
    })


def timed(spp, seed):
    s = scene(spp)
    t = time.time()
    img = mi.render(s, seed=seed, spp=spp)
    if hasattr(img, "numpy"):
        img.numpy()  # wait for the LLVM backend to finish
    return img, time.time() - t


spp = a.spp
if a.seconds is not None:
    timed(2, a.seed + 1000)  # warm-up: JIT compilation, file loading
    probe = 32
    _, dt = timed(probe, a.seed + 2000)
    spp = max(1, round(a.seconds * probe / dt))
img, dt = timed(spp, a.seed)
mi.util.write_bitmap(a.out, img)
print(f"mitsuba {a.variant} {a.sampler}: {w}x{h} spp={spp}: {dt:.3f} s")
