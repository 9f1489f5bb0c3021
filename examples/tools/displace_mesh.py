#!/usr/bin/env python3
"""Displace a mesh along its normals by a height image (a stand-in sculpt).

    displace_mesh.py IN.obj HEIGHT OUT.obj --scale S

IN.obj is what `surfgrad mesh subdivide --limit` writes: positions (v),
texture coordinates (vt, t up), unit normals (vn) and faces "f v/vt/vn".
Each vertex moves once, by S * h along its normal, h in [0,1] the height
image's value at the UV of the vertex's first face corner (bilinear, texel
centres at (i + 0.5) / width, clamped at the border; row 0 of the image is
the TOP row, t = 1). Moving each vertex once keeps the mesh closed across
UV seams. OUT.obj gets the moved positions and the faces (no UVs, no
normals: a high-resolution mesh to bake from).

Needs Python 3 and oiiotool (openimageio-tools), which converts HEIGHT to
the 16-bit grayscale PNG that height_to_normal.py's reader decodes.
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from height_to_normal import read_png_gray16  # noqa: E402


def sample(w, h, vals, s, t):
    x = min(max(s * w - 0.5, 0.0), w - 1.0)
    y = min(max((1.0 - t) * h - 0.5, 0.0), h - 1.0)
    x0, y0 = int(x), int(y)
    x1, y1 = min(x0 + 1, w - 1), min(y0 + 1, h - 1)
    fx, fy = x - x0, y - y0
    top = vals[y0 * w + x0] * (1 - fx) + vals[y0 * w + x1] * fx
    bottom = vals[y1 * w + x0] * (1 - fx) + vals[y1 * w + x1] * fx
    return top * (1 - fy) + bottom * fy


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("input")
    ap.add_argument("height")
    ap.add_argument("output")
    ap.add_argument("--scale", type=float, required=True, help="object units per unit of height")
    a = ap.parse_args()
    if not math.isfinite(a.scale):
        sys.exit("displace_mesh: --scale must be finite")
    with tempfile.TemporaryDirectory() as tmp:
        hpath = os.path.join(tmp, "h.png")
        subprocess.run(["oiiotool", a.height, "--ch", "0", "-d", "uint16", "-o", hpath], check=True)
        w, h, vals = read_png_gray16(hpath)
    pos, uv, nrm, faces = [], [], [], []
    first_uv = {}
    with open(a.input) as f:
        for line in f:
            k = line.split()
            if not k:
                continue
            if k[0] == "v":
                pos.append(tuple(float(x) for x in k[1:4]))
            elif k[0] == "vt":
                uv.append((float(k[1]), float(k[2])))
            elif k[0] == "vn":
                nrm.append(tuple(float(x) for x in k[1:4]))
            elif k[0] == "f":
                corners = [c.split("/") for c in k[1:]]
                vs = [int(c[0]) - 1 for c in corners]
                for c, v in zip(corners, vs):
                    if v not in first_uv:
                        first_uv[v] = (int(c[1]) - 1, int(c[2]) - 1)
                faces.append(vs)
    with open(a.output + ".tmp", "w") as out:
        out.write("# displaced by displace_mesh.py\n")
        for v, p in enumerate(pos):
            if v in first_uv:
                t, n = first_uv[v]
                d = a.scale * sample(w, h, vals, uv[t][0], uv[t][1])
                p = tuple(p[i] + d * nrm[n][i] for i in range(3))
            out.write("v %.7g %.7g %.7g\n" % p)
        for vs in faces:
            out.write("f " + " ".join(str(v + 1) for v in vs) + "\n")
    os.replace(a.output + ".tmp", a.output)
    print("wrote %s (%d vertices, %d faces)" % (a.output, len(pos), len(faces)))


if __name__ == "__main__":
    main()
