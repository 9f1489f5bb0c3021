#!/usr/bin/env python3
"""Bake a tangent-space normal map from a height image (for the examples).

    height_to_normal.py IN OUT.png --depth TEXELS [--size N] [--blur PIXELS]
                        [--wrap repeat|clamp] [--invert]

The height h in [0,1] is the image's luminance (Rec. 709 weights), optionally
resized to N x N and blurred (a bevel for hard-edged art). Each texel stores
the unit normal of the height field z = depth * h over the texel grid,

    n = normalize(-depth * dh/du, -depth * dh/dv, 1),   u right, v UP,

encoded as 0.5 n + 0.5 in 8-bit RGB: the OpenGL / glTF green convention
("green": "gl" in a scene, flipV = false in the library; Mikkelsen 2019,
section 2.1). dh/du, dh/dv are central differences in texel units, wrapping
(tileable maps) or clamping at the border. `depth` is the height of a full
0 -> 1 step measured in texels: larger means steeper bumps.

Needs only Python 3 and oiiotool (openimageio-tools), which reads the input,
resizes and blurs it into a 16-bit grayscale PNG that this script decodes.
"""
import argparse
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib


def read_png_gray16(path):
    """A 16-bit grayscale, non-interlaced PNG (what oiiotool writes with
    -d uint16 for one channel) as floats in [0,1], top row first."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit("height_to_normal: intermediate is not a PNG")
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 16 or ctype != 0 or interlace != 0:
                sys.exit("height_to_normal: expected a 16-bit gray PNG intermediate")
        elif kind == b"IDAT":
            idat += body
    raw, bpp, stride = zlib.decompress(idat), 2, 2 * w
    rows, prev = [], bytearray(stride)
    for y in range(h):  # undo the per-row filters (PNG spec, section 9)
        ftype, row = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = row[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if ftype == 1:
                row[i] = (row[i] + a) & 255
            elif ftype == 2:
                row[i] = (row[i] + b) & 255
            elif ftype == 3:
                row[i] = (row[i] + (a + b) // 2) & 255
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(row)
        prev = row
    vals = []
    for row in rows:
        vals.extend(v / 65535.0 for v in struct.unpack(">%dH" % w, bytes(row)))
    return w, h, vals


def write_png_rgb8(path, w, h, rgb):
    """An 8-bit RGB PNG, top row first."""
    raw = b"".join(b"\0" + bytes(rgb[3 * w * y:3 * w * (y + 1)]) for y in range(h))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--depth", type=float, required=True, help="height of a 0->1 step, in texels")
    ap.add_argument("--size", type=int, default=0, help="resize to N x N first")
    ap.add_argument("--blur", type=int, default=0, help="blur width in pixels (after resizing)")
    ap.add_argument("--wrap", choices=["repeat", "clamp"], default="repeat")
    ap.add_argument("--invert", action="store_true", help="use 1 - h (dark is high)")
    a = ap.parse_args()
    if not (a.depth > 0 and math.isfinite(a.depth)):
        sys.exit("height_to_normal: --depth must be a positive number")

    with tempfile.TemporaryDirectory() as tmp:
        hpath = os.path.join(tmp, "h.png")
        nch = _channels(a.input)
        cmd = ["oiiotool", a.input]
        if nch >= 3:
            cmd += ["--ch", "R,G,B", "--chsum:weight=0.2126,0.7152,0.0722"]
        elif nch == 2:
            cmd += ["--ch", "0"]
        if a.size:
            cmd += ["--resize", "%dx%d" % (a.size, a.size)]
        if a.blur:
            cmd += ["--blur", "%dx%d" % (a.blur, a.blur)]
        subprocess.run(cmd + ["-d", "uint16", "-o", hpath], check=True)
        w, h, hv = read_png_gray16(hpath)
        if a.invert:
            hv = [1.0 - x for x in hv]

        def at(x, y):
            if a.wrap == "repeat":
                x %= w
                y %= h
            else:
                x = min(max(x, 0), w - 1)
                y = min(max(y, 0), h - 1)
            return hv[y * w + x]

        out = bytearray(3 * w * h)
        q = lambda v: max(0, min(255, int(round(v * 255.0))))
        for y in range(h):  # row 0 is the TOP row: +v is -y
            for x in range(w):
                du = 0.5 * (at(x + 1, y) - at(x - 1, y)) * a.depth
                dv = 0.5 * (at(x, y - 1) - at(x, y + 1)) * a.depth
                inv = 1.0 / math.sqrt(1.0 + du * du + dv * dv)
                i = 3 * (y * w + x)
                out[i] = q(0.5 - 0.5 * du * inv)
                out[i + 1] = q(0.5 - 0.5 * dv * inv)
                out[i + 2] = q(0.5 + 0.5 * inv)
    write_png_rgb8(a.output, w, h, out)
    print("wrote %s (%dx%d)" % (a.output, w, h))


def _channels(path):
    r = subprocess.run(["oiiotool", "--info", "-v", path], check=True, capture_output=True, text=True)
    for line in r.stdout.splitlines():
        if " channel" in line and "x" in line:
            # e.g. "file.png : 1024 x 1024, 3 channel, uint8 png"
            for part in line.split(","):
                part = part.strip()
                if part.endswith("channel"):
                    return int(part.split()[0])
    return 1


if __name__ == "__main__":
    main()
