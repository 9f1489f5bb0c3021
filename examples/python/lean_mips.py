#!/usr/bin/env python3
"""A LEAN MIP chain of a tangent-space normal map, written as one OpenEXR file.

    lean_mips.py [NORMAL.png] OUT.exr [--green gl|dx] [--wrap repeat|clamp] [--encoding rgb|rg|ag]

Default input: data/textures/technicalFabricSmall_normal_256.png.

A normal map cannot be MIP-mapped by averaging its normals: the average of bumpy normals points up
and the bumps' roughness is lost, so a distant surface looks too smooth and too shiny. LEAN
mapping (Olano and Baker 2010; Loviscach 2008, "Care: Antialiasing") stores the slopes
d = (dh/du, dh/dv) and their second moments (dx, dy, dxx, dyy, dxy); box filtering is then
exact, and every level gives the mean slope and the slope covariance of its footprint
(cov = (dxx - dx^2, dyy - dy^2, dxy - dx dy)), which a shader turns into a wider specular lobe
(docs/scene.md, "Bump antialiasing"). The file is the one `surfgrad normalmap mips --lean` writes
(docs/normalmap.md, "mips"): every level, 32-bit float channels dx dy dxx dyy dxy, layout lean1.

The script prints, per level, its size, the mean slope and the mean slope variance: the mean is
the same at every level (box filtering keeps it), the variance grows as the detail that the
level can no longer show moves from the slopes into the covariance.
"""
import argparse
import os
import sys
from pathlib import Path

import numpy as np

import surfgrad
from surfgrad import normalmap

DATA_DIR = Path(os.environ.get("SURFGRAD_DATA_DIR", Path(__file__).resolve().parents[2] / "data"))
DEFAULT_INPUT = DATA_DIR / "textures/technicalFabricSmall_normal_256.png"


def lean_chain(path, encoding="rgb", green="gl"):
    """Slopes of the map at `path` (texels, +v up whatever the file's green convention) and
    their LEAN chain, level 0 first: each level (H, W, 5) = (dx, dy, dxx, dyy, dxy)."""
    image, _bits = normalmap.read_image(path)
    slopes = normalmap.decode_slopes(image, encoding, green)
    return slopes, normalmap.mips(slopes, "lean")


def level_statistics(level):
    """Mean slope (2,) and mean covariance (var x, var y, cov xy) of one LEAN level, in double."""
    m = level.astype(np.float64)
    covariance = np.stack(
        [m[..., 2] - m[..., 0] ** 2, m[..., 3] - m[..., 1] ** 2, m[..., 4] - m[..., 0] * m[..., 1]],
        axis=-1,
    )
    return m[..., :2].mean(axis=(0, 1)), covariance.mean(axis=(0, 1))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="+", metavar="PATH", help="[NORMAL.png] OUT.exr")
    parser.add_argument("--green", choices=["gl", "dx"], default="gl")
    parser.add_argument("--wrap", choices=["repeat", "clamp"], default="repeat")
    parser.add_argument("--encoding", choices=["rgb", "rg", "ag"], default="rgb")
    args = parser.parse_args(argv)
    if len(args.paths) > 2:
        parser.error("expected [NORMAL.png] OUT.exr")
    source = Path(args.paths[0]) if len(args.paths) == 2 else DEFAULT_INPUT
    output = Path(args.paths[-1])
    try:
        slopes, levels = lean_chain(source, args.encoding, args.green)
        normalmap.write_mips(output, levels, "lean", args.wrap)
    except surfgrad.InputError as e:
        print(f"lean_mips: error: {e}", file=sys.stderr)
        return 1
    height, width = slopes.shape[:2]
    print(f"{source.name}: {width} x {height}, max |slope| {np.abs(slopes).max():.3f}")
    print("level  size        mean slope (dx, dy)     mean variance (x, y)   mean cov xy")
    for k, level in enumerate(levels):
        mean, cov = level_statistics(level)
        size = f"{level.shape[1]} x {level.shape[0]}"
        print(
            f"{k:5d}  {size:<10}  ({mean[0]:+.5f}, {mean[1]:+.5f})  "
            f"({cov[0]:.5f}, {cov[1]:.5f})   {cov[2]:+.5f}"
        )
    print(f"wrote {output} ({len(levels)} levels, channels dx dy dxx dyy dxy)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
