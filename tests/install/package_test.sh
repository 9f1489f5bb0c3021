#!/usr/bin/env bash
# ctest package_deb (label package): the Debian packages `cpack -G DEB`
# builds from this build directory (cmake/SurfgradInstall.cmake).
#   1. cpack writes surfgrad_<version>_<arch>.deb and surfgrad-dev_...deb;
#   2. control fields: names, version, architecture, a Maintainer
#      "name <email>", sections; surfgrad's Depends comes from dpkg-shlibdeps
#      (libc6, OpenImageIO, OpenSubdiv, ...) plus Mesa's EGL and GL drivers;
#      surfgrad-dev depends on surfgrad (= version) and the -dev packages of
#      the CMake dependencies; every package named is a real Debian package
#      (installed on this machine, where the build found them);
#   3. contents (dpkg-deb -c): the CLI, data, examples in surfgrad; headers,
#      static libraries, CMake package and GLSL library in surfgrad-dev;
#      everything under /usr, owned by root, no file in both packages;
#      the licenses: /usr/share/doc/<package>/copyright in both (Debian's
#      machine-readable format, naming the project's license and every data
#      set of data/README.md with a license paragraph for each license it
#      uses), the Apache License 2.0 text, the manual page surfgrad(1)
#      (gzip, generated from the help texts: every command's section);
#   4. both extracted into a scratch root (dpkg-deb -x): the packaged
#      surfgrad renders the packaged terrain example, finding the packaged
#      data relative to itself.
# A clean Debian 12 root with dpkg -i and apt is scripts/test-package (too
# slow for every test run; docs/install.md).
# Usage: package_test.sh BUILD_DIR SOURCE_DIR WORK_DIR VERSION
set -euo pipefail
build="$1" src="$2" work="$3" version="$4"

fail() { echo "package_test: FAIL: $*" >&2; exit 1; }
t0=$SECONDS
step() { echo "package_test: [$((SECONDS - t0)) s] $*"; }
unset SURFGRAD_DATA_DIR

rm -rf "$work"
mkdir -p "$work"
arch="$(dpkg --print-architecture)"

# ---- 1. build the packages
step "cpack -G DEB"
cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work" >"$work/cpack.log" 2>&1 ||
    { cat "$work/cpack.log" >&2; fail "cpack -G DEB"; }
run="$work/surfgrad_${version}_${arch}.deb"
dev="$work/surfgrad-dev_${version}_${arch}.deb"
[ -f "$run" ] || fail "$(basename "$run") not written: $(ls "$work")"
[ -f "$dev" ] || fail "$(basename "$dev") not written: $(ls "$work")"

# ---- 2. control fields
step "control fields"
field() { dpkg-deb -f "$1" "$2"; }
expect_field() { # deb field value
    [ "$(field "$1" "$2")" = "$3" ] || fail "$(basename "$1"): $2 is '$(field "$1" "$2")', expected '$3'"
}
expect_field "$run" Package surfgrad
expect_field "$dev" Package surfgrad-dev
for deb in "$run" "$dev"; do
    expect_field "$deb" Version "$version"
    expect_field "$deb" Architecture "$arch"
    field "$deb" Maintainer | grep -Eq '^[^<>]+ <[^<>@ ]+@[^<>@ ]+>$' ||
        fail "$(basename "$deb"): Maintainer '$(field "$deb" Maintainer)' is not 'name <email>'"
    # Into a variable first: `grep -q` closing the pipe early can give
    # dpkg-deb a SIGPIPE, which pipefail would report as a failure.
    description="$(field "$deb" Description)"
    [ -n "$description" ] || fail "$(basename "$deb"): no Description"
    grep -q "License: Apache-2.0" <<<"$description" ||
        fail "$(basename "$deb"): the Description does not give the SPDX license Apache-2.0"
done
expect_field "$run" Section graphics
expect_field "$dev" Section libdevel
run_deps="$(field "$run" Depends)"
dev_deps="$(field "$dev" Depends)"
# dpkg-shlibdeps ran (libc6 with a version) and found the shared libraries
# the CLI links; libepoxy dlopens GLVND's libEGL/libGL and they load Mesa's
# drivers, so those are named explicitly (without libegl1 the CLI aborts on
# a clean Debian 12: scripts/test-package).
for want in 'libc6 (>= ' 'libopenimageio' 'libosdcpu' 'libtinygltf' 'libpugixml1v5' 'libepoxy0' \
            'libegl1,' 'libgl1,' 'libegl-mesa0' 'libgl1-mesa-dri'; do
    grep -qF "$want" <<<"$run_deps" || fail "surfgrad Depends lacks $want: $run_deps"
done
# openimageio-tools: OpenImageIO's CMake config fails without its tools.
for want in "surfgrad (= $version)" libglm-dev libopenmesh-dev libosd-dev libopenimageio-dev \
            openimageio-tools libtinygltf-dev libpugixml-dev libtbb-dev libepoxy-dev libegl-dev \
            glslang-dev spirv-tools libspirv-cross-c-shared-dev; do
    grep -qF "$want" <<<"$dev_deps" || fail "surfgrad-dev Depends lacks $want: $dev_deps"
done
# Every package named (alternatives and version constraints stripped) is a
# Debian 12 package: installed here (the build found its files).
for p in $(sed 's/([^)]*)//g; s/[,|]/ /g' <<<"$run_deps, $dev_deps, $(field "$run" Recommends)"); do
    [ "$p" = surfgrad ] && continue
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
        fail "package $p named by the control files is not an installed Debian package"
done

# ---- 3. contents
step "contents"
list() { dpkg-deb -c "$1" | awk '{ print $6 }' | sed 's|^\./|/|'; }
list "$run" >"$work/run.list"
list "$dev" >"$work/dev.list"
has() { grep -qx "$2" "$work/$1.list" || fail "$1 package lacks $2"; }
has run /usr/bin/surfgrad
has run /usr/share/surfgrad/data/README.md
has run /usr/share/surfgrad/data/meshes/spot/spot_control_mesh.obj
has run /usr/share/surfgrad/examples/terrain/scene.json
has run /usr/share/surfgrad/examples/data/rock_normal.png
has run /usr/share/surfgrad/examples/engine-integration/CMakeLists.txt
has run /usr/share/surfgrad/examples/consumer-tangents/main.cpp
has dev /usr/include/surfgrad/bump/core.h
has dev /usr/include/surfgrad/mesh/tangents.h
has dev /usr/include/surfgrad/render/scene.h
has dev /usr/include/surfgrad/bump.h
has dev /usr/include/surfgrad/mesh.h
has dev /usr/include/surfgrad/render.h
has dev /usr/share/surfgrad/shaders/sg/surfgrad.glsl
has dev /usr/share/surfgrad/shaders/sg/compat.glsl
has dev /usr/share/surfgrad/shaders/sg/surfgrad.hlsl
has dev /usr/share/surfgrad/shaders/flat/surfgrad.ush
cfgdir="$(grep -x '/usr/lib.*/cmake/surfgrad/' "$work/dev.list" || true)"
[ -n "$cfgdir" ] || fail "surfgrad-dev has no /usr/lib*/cmake/surfgrad/"
for f in surfgradConfig.cmake surfgradConfigVersion.cmake surfgradTargets.cmake \
         surfgradDependencies.cmake FindOpenSubdiv.cmake; do
    has dev "$cfgdir$f"
done
for m in base shaders bump features mesh image gl parity render normalmap bake; do
    has dev "$(dirname "$(dirname "$cfgdir")")/libsurfgrad_$m.a"
done
# Data: every file of data/ is in the package.
n_src="$(cd "$src/data" && find . -type f | wc -l)"
n_deb="$(grep -c '^/usr/share/surfgrad/data/.*[^/]$' "$work/run.list")"
[ "$n_src" = "$n_deb" ] || fail "surfgrad has $n_deb data files, data/ has $n_src"
# Headers and libraries only in -dev, the CLI only in surfgrad, no file in both.
! grep -q '^/usr/include/\|\.a$' "$work/run.list" || fail "surfgrad holds headers or static libraries"
! grep -qx /usr/bin/surfgrad "$work/dev.list" || fail "surfgrad-dev holds the CLI"
both="$(comm -12 <(grep -v '/$' "$work/run.list" | sort) <(grep -v '/$' "$work/dev.list" | sort))"
[ -z "$both" ] || fail "files in both packages: $both"
! grep -v '^/usr/\|^/$' "$work/run.list" "$work/dev.list" || fail "files outside /usr"
dpkg-deb -c "$run" | awk '$6 == "./usr/bin/surfgrad" { print $1, $2 }' | grep -qx -- '-rwxr-xr-x root/root' ||
    fail "/usr/bin/surfgrad is not -rwxr-xr-x root/root"

# Licenses and the manual page.
has run /usr/share/doc/surfgrad/copyright
has run /usr/share/doc/surfgrad/LICENSE
has dev /usr/share/doc/surfgrad-dev/copyright
has run /usr/share/man/man1/surfgrad.1.gz
! grep -q '^/usr/share/man/' "$work/dev.list" || fail "surfgrad-dev holds a manual page"

# ---- 4. run from the unpacked packages
step "surfgrad render from the unpacked packages"
root="$work/root"
dpkg-deb -x "$run" "$root"
dpkg-deb -x "$dev" "$root"
export LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe EGL_PLATFORM=surfaceless
cd "$work"
"$root/usr/bin/surfgrad" render "$root/usr/share/surfgrad/examples/tessellated-asset/scene.json" \
    -o asset.png --size 64x48 >render.out 2>&1 || { cat render.out >&2; fail "packaged surfgrad render"; }
grep -q "^wrote asset.png (64x48" render.out || fail "render: $(cat render.out)"

step "licenses and the manual page in the unpacked packages"
doc="$root/usr/share/doc/surfgrad"
cmp -s "$doc/LICENSE" "$src/LICENSE" || fail "/usr/share/doc/surfgrad/LICENSE is not LICENSE"
grep -q "Apache License" "$src/LICENSE" && grep -q "Version 2.0, January 2004" "$src/LICENSE" ||
    fail "LICENSE is not the Apache License 2.0"
cmp -s "$doc/copyright" "$root/usr/share/doc/surfgrad-dev/copyright" ||
    fail "the two packages' copyright files differ"
copyright="$doc/copyright"
head -1 "$copyright" | grep -qx 'Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/' ||
    fail "copyright: not in Debian's machine-readable format (first line $(head -1 "$copyright"))"
# The project's own files.
awk '/^Files: \*$/ { f = 1; next } f && /^License:/ { print $2; exit }' "$copyright" | grep -qx Apache-2.0 ||
    fail "copyright: 'Files: *' is not under Apache-2.0"
# Every data set data/README.md lists (its table's folders) has a Files
# paragraph.
sets="$(grep -o '^| `[a-z-]*/[a-z-]*/*`' "$src/data/README.md" | tr -d '|` ')"
[ -n "$sets" ] || fail "no data sets found in data/README.md"
for d in $sets; do
    grep -qx "Files: data/${d%/}/\*" "$copyright" || fail "copyright: no 'Files: data/${d%/}/*' paragraph"
done
# Every license a Files paragraph names (split at 'and'/'or') has its own
# License paragraph, or its text inline (a paragraph with a body).
for lic in $(awk '/^Files:/ { f = 1; next } f && /^License:/ { sub(/^License: */, ""); print; f = 0 }' \
                 "$copyright" | sed 's/ and / /g; s/ or / /g'); do
    awk -v l="$lic" 'BEGIN { ok = 0 }
        /^License: / { cur = $2; next }
        /^[A-Za-z-]+:/ { cur = "" }
        cur == l && /^ / { ok = 1 }
        /^$/ { cur = "" }
        END { exit !ok }' "$copyright" || fail "copyright: license $lic has no text or paragraph"
done
man="$root/usr/share/man/man1/surfgrad.1.gz"
gzip -t "$man" || fail "surfgrad.1.gz is not gzip"
zcat "$man" >"$work/surfgrad.1"
grep -q '^\.TH SURFGRAD 1 ' "$work/surfgrad.1" || fail "surfgrad.1: no .TH SURFGRAD 1"
# Generated from the help texts: every command the CLI lists has a section
# holding its own --help (its first line).
for c in render shader mesh normalmap features bake eval selftest; do
    grep -qx ".SS \"surfgrad $c\"" "$work/surfgrad.1" || fail "surfgrad.1: no section for surfgrad $c"
done
grep -qx '.SS "surfgrad mesh info"' "$work/surfgrad.1" || fail "surfgrad.1: no section for surfgrad mesh info"
first="$("$root/usr/bin/surfgrad" render --help | head -1 | sed 's/\\/\\e/g')"
! grep -qF "$build" "$work/surfgrad.1" || fail "surfgrad.1 names the build directory $build"
grep -qF -- "$first" "$work/surfgrad.1" || fail "surfgrad.1 lacks 'surfgrad render --help' ($first)"
if command -v man >/dev/null; then
    MANWIDTH=100 man -l "$work/surfgrad.1" >"$work/surfgrad.1.txt" 2>"$work/man.err" ||
        fail "man -l surfgrad.1: $(cat "$work/man.err")"
    ! grep -q 'warning' "$work/man.err" || fail "man -l surfgrad.1: $(cat "$work/man.err")"
fi

# ---- 5. python3-surfgrad (when the module was built): control fields,
# contents, and `import surfgrad` from the unpacked package.
if [ -n "${SURFGRAD_PYTHON:-}" ]; then
    step "python3-surfgrad"
    py="$work/python3-surfgrad_${version}_${arch}.deb"
    [ -f "$py" ] || fail "$(basename "$py") not written: $(ls "$work")"
    expect_field "$py" Package python3-surfgrad
    expect_field "$py" Version "$version"
    expect_field "$py" Section python
    py_deps="$(field "$py" Depends)"
    for want in "surfgrad (= $version)" 'python3 (>= 3.' 'python3 (<< 3.' python3-numpy 'libc6 (>= ' \
                'libtbb' 'libopenimageio' 'libegl1'; do
        grep -qF "$want" <<<"$py_deps" || fail "python3-surfgrad Depends lacks $want: $py_deps"
    done
    list "$py" >"$work/py.list"
    for f in __init__.py __init__.pyi normalmap.pyi features.pyi py.typed; do
        has py "/usr/lib/python3/dist-packages/surfgrad/$f"
    done
    grep -q '^/usr/lib/python3/dist-packages/surfgrad/_surfgrad.*\.so$' "$work/py.list" ||
        fail "python3-surfgrad lacks the extension module"
    has py /usr/share/doc/python3-surfgrad/copyright
    both="$(comm -12 <(grep -v '/$' "$work/run.list" "$work/dev.list" | cut -d: -f2 | sort) \
                     <(grep -v '/$' "$work/py.list" | sort))"
    [ -z "$both" ] || fail "files in python3-surfgrad and another package: $both"
    dpkg-deb -x "$py" "$root"
    PYTHONPATH="$root/usr/lib/python3/dist-packages" "$SURFGRAD_PYTHON" -c '
import os, sys, surfgrad
real = os.path.realpath
assert real(surfgrad.__file__).startswith(real(sys.argv[1])), surfgrad.__file__
cage = surfgrad.load_cage(sys.argv[2])
print(cage.vertex_count, cage.face_count)' "$root/usr/lib/python3/dist-packages" \
        "$root/usr/share/surfgrad/data/meshes/spot/spot_control_mesh.obj" >py.out 2>&1 ||
        { cat py.out >&2; fail "import surfgrad from the unpacked python3-surfgrad"; }
fi
step "passed"
