#!/usr/bin/env python3
# The folder-level dependency rule of docs/architecture.md ("Layout and
# dependency order"), run by the ctest module_includes: a file of a module's
# folder includes only
#   - files of its own folder, or
#   - public files (include/ trees; the GLSL library shaders/sg) of the
#     modules its target reaches by linking (build/module_links.txt, whose
#     graph the ctest module_links checks against the rules).
# So no file of the shader library includes a header of a library above it,
# and no program includes a library's private header (src/), whatever the
# include paths of a target happen to allow. Quoted includes of C++ and GLSL
# (`#include "..."`, also inside GLSL held in C++ strings) are resolved
# against the including file's folder and every module's folder; an include
# that resolves to no file of the tree (system headers, generated files) is
# not a first-party edge.
#
# It also checks the layout of the public headers (docs/architecture.md,
# "Public headers"): a module folder M/'s include trees hold only
# surfgrad/M/<name>.h and the module's umbrella header surfgrad/M.h, and the
# umbrella names every header of surfgrad/M/ (includes it, or says in a
# comment why not).
#
# Usage: module_includes.py SOURCE_DIR module_links.txt module_dirs.txt
# Exit status 1 names every offending include: file, line, header, why.
import os
import re
import sys

INCLUDE_RE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
SOURCE_EXTS = (".h", ".hpp", ".cpp", ".glsl", ".hlsl", ".in")
# Targets that are modules: libraries surfgrad_<name> and the CLI.
MODULE_RE = re.compile(r"^surfgrad(_[a-z]+)?$")


def read_table(path):
    rows = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if "|" in line:
                name, rest = line.split("|", 1)
                rows[name] = rest
    return rows


def reach(links, start):
    """Every target `start` reaches through first-party links."""
    seen, todo = set(), [start]
    while todo:
        cur = todo.pop()
        for dep in links.get(cur, []):
            if dep in links and dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return seen


def public_roots(folder):
    """Where other modules may include a module's files from."""
    roots = [os.path.join(folder, "include")]
    if os.path.basename(folder) == "shaders":
        roots.append(folder)  # the GLSL library: "sg/..." paths
    return roots


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: module_includes.py SOURCE_DIR module_links.txt module_dirs.txt")
    src = os.path.realpath(sys.argv[1])
    raw_links = read_table(sys.argv[2])
    # Generator expressions LINK_LIBRARIES keeps unevaluated: a target
    # named conditionally counts as linked (as in CheckModuleLinks.cmake).
    genex = re.compile(r"\$<(?:TARGET_NAME_IF_EXISTS|LINK_ONLY|BUILD_INTERFACE):([^>]*)>")
    links = {
        t: [d for d in genex.sub(r"\1", v).split(";") if d]
        for t, v in raw_links.items()
        if v != "#not-configured"
    }
    dirs = {t: os.path.realpath(d) for t, d in read_table(sys.argv[3]).items()}

    # Folder -> the module targets defined there (a folder may hold a
    # module and its tools, e.g. shaders/ and surfgrad_flatten).
    folders = {}
    for t, d in dirs.items():
        if MODULE_RE.match(t) and t in links and d != src:
            folders.setdefault(d, set()).add(t)
    if not folders:
        sys.exit("module_includes: no module folders in %s" % sys.argv[3])
    # Each folder may include its own files and the public files of what
    # its targets reach.
    allowed = {}
    for d, targets in folders.items():
        ok = set()
        for t in targets:
            ok |= reach(links, t)
        allowed[d] = {dirs[t] for t in ok if t in dirs} - {d}

    def owner(path):
        best = None
        for d in folders:
            if path.startswith(d + os.sep) and (best is None or len(d) > len(best)):
                best = d
        return best

    errors, checked = [], 0
    for d in sorted(folders):
        errors += header_layout(d, folders, src)
        for root, subdirs, files in os.walk(d):
            # A nested module folder (apps/viewer inside apps/) is its own.
            subdirs[:] = [s for s in subdirs if os.path.join(root, s) not in folders]
            for name in sorted(files):
                if not name.endswith(SOURCE_EXTS):
                    continue
                path = os.path.join(root, name)
                checked += 1
                with open(path, encoding="utf-8", errors="replace") as f:
                    lines = f.readlines()
                for lineno, line in enumerate(lines, 1):
                    m = INCLUDE_RE.match(line)
                    if not m:
                        continue
                    inc = m.group(1)
                    local = os.path.realpath(os.path.join(root, inc))
                    if os.path.isfile(local):
                        # Relative to the file: its own folder's, or (a path
                        # with ..) a file of another module, judged by where
                        # it lies.
                        other = owner(local)
                        err = None if other == d else placed(local, other, d, folders, allowed)
                    else:
                        err = classify(inc, d, folders, allowed)
                    if err:
                        rel = os.path.relpath(path, src)
                        errors.append('%s:%d: #include "%s": %s' % (rel, lineno, inc, err))
    if errors:
        print("module_includes: includes that break the dependency order, or misplaced "
              "public headers:", file=sys.stderr)
        for e in errors:
            print("  " + e, file=sys.stderr)
        return 1
    print("module_includes: %d files of %d module folders include only what their modules link"
          % (checked, len(folders)))
    return 0


def include_roots(folder, folders):
    """The public include trees of a module folder: its include/ and those
    of the folders inside it (mesh/oracle/include), not of nested modules."""
    roots = []
    for root, subdirs, _ in os.walk(folder):
        if os.path.basename(root) == "include":
            roots.append(root)
            subdirs[:] = []
        subdirs[:] = [s for s in subdirs
                      if s not in ("src", "sg") and os.path.join(root, s) not in folders]
    return sorted(roots)


def header_layout(folder, folders, src):
    """Errors of the public header layout of one module folder."""
    mod = os.path.basename(folder)
    umbrella = os.path.join(folder, "include", "surfgrad", mod + ".h")
    errors, headers = [], []
    for root in include_roots(folder, folders):
        for cur, _, files in os.walk(root):
            for name in sorted(files):
                path = os.path.join(cur, name)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                if rel.startswith("surfgrad/%s/" % mod):
                    headers.append(rel)
                elif not (rel == "surfgrad/%s.h" % mod and path == umbrella):
                    errors.append("%s: a public header outside surfgrad/%s/ (its place: "
                                  "surfgrad/%s/%s)" % (os.path.relpath(path, src), mod, mod,
                                                       os.path.basename(rel)))
    if headers:
        if not os.path.isfile(umbrella):
            errors.append("%s: missing: the umbrella header of %s/ (names every header of "
                          "surfgrad/%s/)" % (os.path.relpath(umbrella, src), mod, mod))
        else:
            with open(umbrella, encoding="utf-8", errors="replace") as f:
                text = f.read()
            for rel in sorted(set(headers)):
                if not re.search(re.escape(rel) + r"(?![\w/])", text):
                    errors.append("%s: the umbrella header does not name %s"
                                  % (os.path.relpath(umbrella, src), rel))
    return errors


def verdict(other, public, folder, folders, allowed):
    name = "/".join(sorted(folders[other]))
    if public:
        if other in allowed[folder]:
            return None
        return "a header of %s, which this folder's module does not link" % name
    return "a private header of %s (%s/src)" % (name, os.path.basename(other))


def placed(path, other, folder, folders, allowed):
    """The verdict on a file found at `path`, in module folder `other` (or
    outside every module folder: None)."""
    if other is None:
        return None
    public = any(path.startswith(r + os.sep) for r in public_roots(other))
    return verdict(other, public, folder, folders, allowed)


def classify(inc, folder, folders, allowed):
    """None when `inc` (not found beside the file) is allowed in `folder`."""
    own = [os.path.join(folder, "src"), os.path.join(folder, "include")] + public_roots(folder)
    if any(os.path.isfile(os.path.join(r, inc)) for r in own):
        return None
    for other in sorted(folders):
        if other == folder:
            continue
        if any(os.path.isfile(os.path.join(r, inc)) for r in public_roots(other)):
            return verdict(other, True, folder, folders, allowed)
        if os.path.isfile(os.path.join(other, "src", inc)):
            return verdict(other, False, folder, folders, allowed)
    return None


if __name__ == "__main__":
    sys.exit(main())
