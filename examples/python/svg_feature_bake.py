#!/usr/bin/env python3
"""Bake an SVG drawing into feature maps and render its curves as V-grooves, magnified.

    svg_feature_bake.py [ICON.svg] OUT.png [--size 64] [--pixels 512] [--window X0 Y0 X1 Y1]
                        [--width 1.5] [--mode linear|quadratic] [--maps OUT.exr]

Default input: data/svg/flame.svg (a Lucide icon, data/svg/README.md).

Feature maps (Parilov, Rosenberg, Zorin 2005; Parilov, Zorin 2008; docs/features.md) store per
texel the pieces of the curves that pass through it and the distances at its corners, so the
distance to the curves (and its gradient, and the side) can be reconstructed exactly at any
magnification: a 64^2 map drawn on 512^2 pixels still shows sharp corners where a bilinear
distance texture would round them. This script samples the maps at every pixel centre of the
image, as the shader does (FeatureMaps.sample), turns the distance into a V-groove height
h = -(w - dist) for dist < w (w = --width texels) with slopes -grad(dist), and lights the
resulting normals (surfgrad.normalmap.shade). --window X0 Y0 X1 Y1 picks a close-up in texel
space ((0, 0) the lower-left corner of the map, y up); --maps also saves the baked maps as
OpenEXR (the file a scene's `feature` layer reads).
"""
import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

import surfgrad
from surfgrad import features, normalmap

DATA_DIR = Path(os.environ.get("SURFGRAD_DATA_DIR", Path(__file__).resolve().parents[2] / "data"))
DEFAULT_INPUT = DATA_DIR / "svg/flame.svg"


def pixel_centres(pixels, window):
    """Texel-space positions (pixels^2, 2) of the pixel centres of a square image covering
    `window` = (x0, y0, x1, y1), row 0 at the bottom (the grid convention of surfgrad)."""
    x0, y0, x1, y1 = window
    steps = (np.arange(pixels) + 0.5) / pixels
    y, x = np.meshgrid(y0 + steps * (y1 - y0), x0 + steps * (x1 - x0), indexing="ij")
    return np.stack([x.ravel(), y.ravel()], axis=1).astype(np.float32)


def groove_slopes(sample, pixels, width_texels):
    """Slopes (pixels, pixels, 2) of the V-groove height h = -(w - dist) inside the groove, per
    texel of the map: dh/dp = grad(dist) there, 0 outside."""
    inside = sample["dist"] < width_texels
    slopes = np.where(inside[:, None], sample["grad"], 0.0)
    return np.ascontiguousarray(slopes.reshape(pixels, pixels, 2), dtype=np.float32)


def render_grooves(maps, pixels, window, width_texels):
    sample = maps.sample(pixel_centres(pixels, window))
    slopes = groove_slopes(sample, pixels, width_texels)
    return normalmap.shade(normalmap.normals_from_slopes(slopes)), sample


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="+", metavar="PATH", help="[ICON.svg] OUT.png")
    parser.add_argument("--size", type=int, default=64, help="map size in texels")
    parser.add_argument("--pixels", type=int, default=512, help="image side in pixels")
    parser.add_argument("--window", type=float, nargs=4, metavar=("X0", "Y0", "X1", "Y1"))
    parser.add_argument("--width", type=float, default=1.5, help="groove half-width, texels")
    parser.add_argument("--mode", choices=["linear", "quadratic"], default="quadratic")
    parser.add_argument("--maps", type=Path, help="also save the baked maps (.exr)")
    args = parser.parse_args(argv)
    if len(args.paths) > 2:
        parser.error("expected [ICON.svg] OUT.png")
    source = Path(args.paths[0]) if len(args.paths) == 2 else DEFAULT_INPUT
    output = Path(args.paths[-1])
    window = args.window or (0.0, 0.0, float(args.size), float(args.size))
    try:
        start = time.perf_counter()
        maps = features.bake(source, size=args.size, mode=args.mode)
        baked = time.perf_counter() - start
        image, sample = render_grooves(maps, args.pixels, window, args.width)
        normalmap.write_image(output, image)
        if args.maps:
            maps.save(args.maps)
    except surfgrad.InputError as e:  # names the file, the element and the reason
        print(f"svg_feature_bake: error: {e}", file=sys.stderr)
        return 1
    magnification = args.pixels / max(window[2] - window[0], window[3] - window[1])
    grooved = float((sample["dist"] < args.width).mean())
    print(f"{source.name}: {args.size}^2 {maps.mode} maps baked in {baked * 1e3:.0f} ms")
    print(f"  {args.pixels}^2 pixels, {magnification:.1f} per texel; {grooved:.1%} in a groove")
    print(f"wrote {output}" + (f" and {args.maps}" if args.maps else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
