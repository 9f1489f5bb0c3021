#!/usr/bin/env python3
"""Write the blendshape example's model: a UV sphere with two morph targets.

    make_morph_blob.py OUT.gltf   (writes OUT.gltf and OUT.bin beside it)

Why a generated model: none of the shared glTF morph samples has both
texture coordinates and normal deltas (AnimatedMorphSphere/Cube have no UVs;
MorphPrimitivesTest has no normal deltas), and a normal-mapped blendshape
needs both. This one is small (64 x 32 segments) and exact:

  base     unit sphere, s around (s = 0.5 faces +z), t from the south pole;
           texture coordinate (4 s, 2 t) so a tileable normal map repeats
           4 x 2 (square tiles at the equator; (4 s, 2 t) = (2, 1) faces +z).
           glTF's texture origin is the top-left corner (v down), so
           TEXCOORD_0 stores (4 s, 1 - 2 t): a reader that flips v to the
           lower-left convention, as surfgrad does, gets (4 s, 2 t) back;
           NORMAL exact;
  target 0 "squash": (x, y, z) -> (1.22 x, 0.62 y, 1.22 z);
  target 1 "lobes":  radius 1 + 0.28 sin(3 phi) sin(theta)^2, three lobes
           around the equator that vanish smoothly at the poles.

Each target stores POSITION and NORMAL deltas (the target's exact normal
minus the base normal, from central differences of the parametric
surface); no TANGENT attribute: the renderer builds the frame per pixel, or
computes MikkTSpace tangents of the base shape when a scene asks for them.
No animation: the scene animates the weights. Written by surfgrad; CC0.
"""
import json
import math
import os
import struct
import sys

NS, NT = 64, 32


def sin_theta(theta):
    """sin(theta), exactly 0 at the north pole: math.sin(math.pi) is 1.2e-16,
    which would give the 65 north-pole vertices 65 different positions, and
    a cage welded by exact position would then have a hole there."""
    return 0.0 if theta == math.pi else math.sin(theta)


def base(phi, theta):
    return (sin_theta(theta) * math.sin(phi), -math.cos(theta), sin_theta(theta) * math.cos(phi))


def squash(phi, theta):
    x, y, z = base(phi, theta)
    return (1.22 * x, 0.62 * y, 1.22 * z)


def lobes(phi, theta):
    r = 1.0 + 0.28 * math.sin(3.0 * phi) * sin_theta(theta) ** 2
    x, y, z = base(phi, theta)
    return (r * x, r * y, r * z)


def normal(surface, phi, theta, pole):
    """Unit normal from central differences; at the poles the surfaces above
    all have normal (0, -1, 0) (south) or (0, 1, 0) (north)."""
    if pole:
        return (0.0, -1.0 if theta < 1.0 else 1.0, 0.0)
    h = 1e-4
    a = [(p - q) / (2 * h) for p, q in zip(surface(phi + h, theta), surface(phi - h, theta))]
    b = [(p - q) / (2 * h) for p, q in zip(surface(phi, theta + h), surface(phi, theta - h))]
    # d/dphi x d/dtheta points outward for this parametrization.
    n = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    l = math.sqrt(sum(c * c for c in n))
    return tuple(c / l for c in n)


def main():
    if len(sys.argv) != 2 or not sys.argv[1].endswith(".gltf"):
        sys.exit("usage: make_morph_blob.py OUT.gltf")
    out = sys.argv[1]
    binName = os.path.splitext(os.path.basename(out))[0] + ".bin"

    pos, nrm, uv = [], [], []
    dpos = [[], []]
    dnrm = [[], []]
    for j in range(NT + 1):
        for i in range(NS + 1):
            s, t = i / NS, j / NT
            # The seam's two columns (s = 0 and 1) are one meridian: the
            # same geometry bit for bit (phi = -pi and pi would differ by
            # sin's rounding), so a cage welded by exact position closes.
            phi, theta = 2.0 * math.pi * ((i % NS) / NS - 0.5), math.pi * t
            pole = j in (0, NT)
            p0, n0 = base(phi, theta), normal(base, phi, theta, pole)
            pos.append(p0)
            nrm.append(n0)
            uv.append((4.0 * s, 1.0 - 2.0 * t))  # glTF v points down
            for k, surf in enumerate((squash, lobes)):
                p1, n1 = surf(phi, theta), normal(surf, phi, theta, pole)
                dpos[k].append(tuple(a - b for a, b in zip(p1, p0)))
                dnrm[k].append(tuple(a - b for a, b in zip(n1, n0)))
    idx = []
    row = NS + 1
    for j in range(NT):
        for i in range(NS):
            a, b, c, d = j * row + i, j * row + i + 1, (j + 1) * row + i, (j + 1) * row + i + 1
            # Counter-clockwise from outside; the pole rows' zero-area halves are left out.
            if j != 0:
                idx += [a, b, d]
            if j != NT - 1:
                idx += [a, d, c]

    blob = bytearray()
    views, accessors = [], []

    def add(values, comps, ctype, target=None, minmax=False):
        while len(blob) % 4:
            blob.append(0)
        off = len(blob)
        fmt = "<" + ("I" if ctype == 5125 else "f") * comps
        for v in values:
            blob.extend(struct.pack(fmt, *(v if comps > 1 else (v,))))
        view = {"buffer": 0, "byteOffset": off, "byteLength": len(blob) - off}
        if target:
            view["target"] = target
        views.append(view)
        acc = {"bufferView": len(views) - 1, "componentType": ctype, "count": len(values),
               "type": {1: "SCALAR", 2: "VEC2", 3: "VEC3"}[comps]}
        if minmax:
            acc["min"] = [min(v[c] for v in values) for c in range(comps)]
            acc["max"] = [max(v[c] for v in values) for c in range(comps)]
        accessors.append(acc)
        return len(accessors) - 1

    aPos = add(pos, 3, 5126, 34962, True)
    aNrm = add(nrm, 3, 5126, 34962)
    aUv = add(uv, 2, 5126, 34962)
    targets = []
    for k in range(2):
        targets.append({"POSITION": add(dpos[k], 3, 5126, 34962, True), "NORMAL": add(dnrm[k], 3, 5126, 34962)})
    aIdx = add(idx, 1, 5125, 34963)

    doc = {
        "asset": {"version": "2.0", "generator": "surfgrad examples/tools/make_morph_blob.py",
                  "copyright": "CC0-1.0 (generated)"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "blob"}],
        "meshes": [{"name": "blob", "weights": [0.0, 0.0],
                    "extras": {"targetNames": ["squash", "lobes"]},
                    "primitives": [{"attributes": {"POSITION": aPos, "NORMAL": aNrm, "TEXCOORD_0": aUv},
                                    "indices": aIdx, "mode": 4, "targets": targets}]}],
        "buffers": [{"uri": binName, "byteLength": len(blob)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(os.path.join(os.path.dirname(out) or ".", binName), "wb") as f:
        f.write(blob)
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print("wrote %s (%d vertices, %d triangles, 2 targets)" % (out, len(pos), len(idx) // 3))


if __name__ == "__main__":
    main()
