#!/usr/bin/env python3
# The ctest module_includes_catches: module_includes.py on a made-up tree of
# three modules (low <- mid, and a shader library), in which one file of
# each kind breaks the order, and one public header of each kind breaks the
# layout (surfgrad/<module>/ and the umbrella surfgrad/<module>.h naming
# them all). The check must fail and name exactly those includes and
# headers; the same tree without them must pass.
import os
import subprocess
import sys
import tempfile

CHECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "module_includes.py")


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def run(root):
    links = os.path.join(root, "links.txt")
    dirs = os.path.join(root, "dirs.txt")
    with open(links, "w") as f:
        f.write("surfgrad_shaders|\nsurfgrad_low|surfgrad_shaders\nsurfgrad_mid|surfgrad_low\n")
    with open(dirs, "w") as f:
        for m in ("shaders", "low", "mid"):
            f.write("surfgrad_%s|%s\n" % (m, os.path.join(root, m)))
    return subprocess.run([sys.executable, CHECK, root, links, dirs], capture_output=True,
                          text=True)


with tempfile.TemporaryDirectory() as root:
    write(root, "shaders/sg/a.glsl", '#include "sg/b.glsl"\n')
    write(root, "shaders/sg/b.glsl", "\n")
    write(root, "low/include/surfgrad/low/a.h", '#include "sg/a.glsl"\n')
    write(root, "low/include/surfgrad/low.h", '#include "surfgrad/low/a.h"\n')
    write(root, "low/src/private.h", "\n")
    write(root, "low/src/low.cpp", '#include "private.h"\n#include "surfgrad/low/a.h"\n')
    write(root, "mid/include/surfgrad/mid/b.h", '#include "surfgrad/low.h"\n')
    write(root, "mid/include/surfgrad/mid/c.h", "\n")
    write(root, "mid/include/surfgrad/mid.h",
          '#include "surfgrad/mid/b.h"\n// surfgrad/mid/c.h: not included (a reason)\n')
    write(root, "mid/src/mid.cpp", '#include "surfgrad/mid.h"\n#include <vector>\n')
    ok = run(root)
    if ok.returncode != 0:
        sys.exit("a tree that keeps the order failed:\n" + ok.stderr)
    # One include of each forbidden kind.
    write(root, "shaders/sg/c.glsl", '#include "surfgrad/low.h"\n')  # a module above
    write(root, "mid/src/bad.cpp", '#include "private.h"\n')  # another's private header
    write(root, "low/src/up.cpp", '#include "surfgrad/mid/b.h"\n')  # against the links
    write(root, "shaders/sg/d.glsl", '#include "../../low/src/private.h"\n')  # by a relative path
    # One public header of each misplaced kind.
    write(root, "low/include/surfgrad/flat.h", "\n")  # outside surfgrad/low/
    write(root, "mid/include/surfgrad/mid/d.h", "\n")  # not named by the umbrella
    write(root, "shaders/include/surfgrad/shaders/e.h", "\n")  # no umbrella at all
    bad = run(root)
    want = [
        'shaders/sg/d.glsl:1: #include "../../low/src/private.h": a private header of surfgrad_low',
        'shaders/sg/c.glsl:1: #include "surfgrad/low.h": a header of surfgrad_low',
        'mid/src/bad.cpp:1: #include "private.h": a private header of surfgrad_low',
        'low/src/up.cpp:1: #include "surfgrad/mid/b.h": a header of surfgrad_mid',
    ]
    layout = [
        "low/include/surfgrad/flat.h: a public header outside surfgrad/low/",
        "mid/include/surfgrad/mid.h: the umbrella header does not name surfgrad/mid/d.h",
        "shaders/include/surfgrad/shaders.h: missing: the umbrella header of shaders/",
    ]
    missing = [w for w in want + layout if w not in bad.stderr]
    if (bad.returncode != 1 or missing or bad.stderr.count("#include") != len(want)
            or bad.stderr.count("\n  ") != len(want) + len(layout)):
        sys.exit("expected exactly %s, got (rc %d):\n%s" % (want + layout, bad.returncode,
                                                            bad.stderr))
print("module_includes catches a shader file, a private header, an upward include and "
      "misplaced public headers")
