#!/usr/bin/env bash
# ctest install_consumers (label install): surfgrad used as an installed
# package, the way another project uses it.
#   1. `cmake --install` into a temporary prefix, then the prefix is MOVED
#      (everything below must work from a relocated installation);
#   2. the installed layout: the CLI, exactly the public headers of the
#      modules, the static libraries, the CMake package files, the GLSL
#      library, data/ and examples/; no path of the build machine in the
#      package's CMake files;
#   3. the installed examples/engine-integration and examples/consumer-tangents
#      are configured and built OUT OF TREE with find_package(surfgrad) and
#      -DCMAKE_PREFIX_PATH=<prefix>, and run: the engine sample's image is
#      byte-identical to the build tree's; consumer-tangents' counts equal
#      the installed CLI's for the same mesh and its frame checks hold;
#   4. a consumer shader including "sg/surfgrad.glsl" validates with
#      glslangValidator given only -I<prefix>/share/surfgrad/shaders (and
#      fails without it), the directory the config reports;
#   5. the installed `surfgrad render share/surfgrad/examples/terrain/scene.json`
#      works, "data:" resolves to the installation's data (a file that exists
#      only there is found), and $SURFGRAD_DATA_DIR overrides it; the
#      installed scenes name their maps through "data:" and render when
#      copied out of the installation.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR ENGINE_SAMPLE_BIN
#        GENERATOR MAKE_PROGRAM CXX_COMPILER BUILD_TYPE
set -euo pipefail
build="$1" src="$2" work="$3" engine_in_tree="$4"
generator="$5" make_program="$6" cxx="$7" build_type="${8:-Release}"

fail() { echo "install_test: FAIL: $*" >&2; exit 1; }
t0=$SECONDS
step() { echo "install_test: [$((SECONDS - t0)) s] $*"; }
# The tests' environment points SURFGRAD_DATA_DIR at the source tree; an
# installed program must find its data without it.
unset SURFGRAD_DATA_DIR

rm -rf "$work"
mkdir -p "$work"
staged="$work/staged"
prefix="$work/moved prefix" # a space: paths must be quoted everywhere

# ---- 1. install, relocate
step "cmake --install $build --prefix $staged"
cmake --install "$build" --prefix "$staged" >"$work/install.log" || fail "cmake --install (see $work/install.log)"
mv "$staged" "$prefix"

# ---- 2. layout
step "checking the installed layout"
# lib/, or lib/<multiarch>/ when the build was configured for /usr.
config="$(cd "$prefix" && find . -path '*/cmake/surfgrad/surfgradConfig.cmake' | head -1)"
[ -n "$config" ] || fail "no <libdir>/cmake/surfgrad/surfgradConfig.cmake in the prefix"
libdir="$(dirname "$(dirname "$(dirname "${config#./}")")")"
[ -x "$prefix/bin/surfgrad" ] || fail "bin/surfgrad missing"
for m in base shaders bump features mesh image gl parity render normalmap bake; do
    [ -f "$prefix/$libdir/libsurfgrad_$m.a" ] || fail "$libdir/libsurfgrad_$m.a missing"
done
for f in surfgradConfig.cmake surfgradConfigVersion.cmake surfgradTargets.cmake \
         surfgradDependencies.cmake FindOpenSubdiv.cmake; do
    [ -f "$prefix/$libdir/cmake/surfgrad/$f" ] || fail "$libdir/cmake/surfgrad/$f missing"
done
# Headers: exactly the modules' include/ trees (internal headers stay out).
(cd "$src" && for d in base shaders image mesh bump features gl parity render normalmap bake translate apps/viewer; do
     (cd "$d/include" && find . -name '*.h'); done) | sort >"$work/headers.want"
(cd "$prefix/include" && find . -type f) | sort >"$work/headers.got"
diff -u "$work/headers.want" "$work/headers.got" >&2 || fail "installed headers differ from the modules' include/ trees"
# Every module's umbrella header (docs/architecture.md, "Public headers").
for m in base shaders image mesh bump features gl parity render normalmap bake translate viewer; do
    [ -f "$prefix/include/surfgrad/$m.h" ] || fail "include/surfgrad/$m.h (the umbrella of $m) missing"
done
# GLSL library and data: the same files as the source tree.
diff <(cd "$src/shaders/sg" && find . -name '*.glsl' -o -name '*.hlsl' | sort) \
     <(cd "$prefix/share/surfgrad/shaders/sg" && find . -type f | sort) >&2 ||
    fail "share/surfgrad/shaders/sg differs from shaders/sg"
# The single-file library (docs/engines.md), as the build wrote it.
for f in surfgrad.glsl surfgrad.hlsl surfgrad.ush; do
    cmp -s "$build/shaders/flat/$f" "$prefix/share/surfgrad/shaders/flat/$f" ||
        fail "share/surfgrad/shaders/flat/$f is not the build's shaders/flat/$f"
done
diff -r "$src/data" "$prefix/share/surfgrad/data" >/dev/null || fail "share/surfgrad/data differs from data/"
for f in terrain/scene.json data/rock_normal.png engine-integration/CMakeLists.txt \
         engine-integration/bumped.frag consumer-tangents/main.cpp; do
    [ -f "$prefix/share/surfgrad/examples/$f" ] || fail "share/surfgrad/examples/$f missing"
done
[ ! -e "$prefix/share/surfgrad/examples/CMakeLists.txt" ] || fail "examples/CMakeLists.txt (build-tree only) installed"
# Relocatable: the package's CMake files name no directory of this machine.
if grep -rlF -e "$src" -e "$build" -e "$staged" "$prefix/$libdir/cmake/surfgrad"; then
    fail "the files above name the source, build or staging directory"
fi

# ---- 3. out-of-tree consumers
configure_build() { # name
    local name="$1"
    step "configure + build examples/$name against the installed package"
    cmake -S "$prefix/share/surfgrad/examples/$name" -B "$work/build-$name" -G "$generator" \
          -DCMAKE_MAKE_PROGRAM="$make_program" -DCMAKE_CXX_COMPILER="$cxx" \
          -DCMAKE_BUILD_TYPE="$build_type" -DCMAKE_PREFIX_PATH="$prefix" \
          >"$work/configure-$name.log" 2>&1 || { cat "$work/configure-$name.log" >&2; fail "configuring $name"; }
    cmake --build "$work/build-$name" >"$work/build-$name.log" 2>&1 ||
        { cat "$work/build-$name.log" >&2; fail "building $name"; }
}
configure_build consumer-tangents
configure_build engine-integration

# The config reports the installed directories (consumer-tangents prints them).
grep -qF "surfgrad_SHADER_DIR=$prefix/share/surfgrad/shaders" "$work/configure-consumer-tangents.log" ||
    fail "surfgrad_SHADER_DIR is not $prefix/share/surfgrad/shaders: $(grep surfgrad_ "$work/configure-consumer-tangents.log")"
grep -qF "surfgrad_SHADER_FLAT_DIR=$prefix/share/surfgrad/shaders/flat" "$work/configure-consumer-tangents.log" ||
    fail "surfgrad_SHADER_FLAT_DIR is not $prefix/share/surfgrad/shaders/flat"
grep -qF "surfgrad_DATA_DIR=$prefix/share/surfgrad/data" "$work/configure-consumer-tangents.log" ||
    fail "surfgrad_DATA_DIR is not $prefix/share/surfgrad/data"

step "run consumer-tangents"
mesh="$prefix/share/surfgrad/data/meshes/spot/spot_control_mesh.obj"
out="$("$work/build-consumer-tangents/example_consumer_tangents" "$mesh")" || fail "consumer-tangents failed"
echo "$out"
# Counts after MikkTSpace's vertex splits: the installed CLI computes the
# same tangents through the same library.
cli="$("$prefix/bin/surfgrad" mesh tangents "$mesh" -o "$work/spot_tangents.glb" --json)" ||
    fail "surfgrad mesh tangents failed"
cli_v="$(sed -n 's/.*"vertices":\([0-9]*\).*/\1/p' <<<"$cli")"
cli_t="$(sed -n 's/.*"triangles":\([0-9]*\).*/\1/p' <<<"$cli")"
grep -qx "vertices $cli_v triangles $cli_t uv_set 0" <<<"$out" ||
    fail "consumer-tangents counts differ from the CLI's (vertices $cli_v, triangles $cli_t)"
read -r _ _ len_err _ dot_n <<<"$(grep '^tangent ' <<<"$out")"
read -r _ _ angle <<<"$(grep '^bump ' <<<"$out")"
# Unit tangents orthogonal to the normals: MikkTSpace normalizes and
# projects in float, so both are rounding-sized (~1e-7); 1e-5 leaves room
# and still catches a wrong frame (errors of 1e-2 and more).
awk -v a="$len_err" -v b="$dot_n" 'BEGIN { exit !(a < 1e-5 && b < 1e-5) }' ||
    fail "tangent frames not orthonormal: length error $len_err, |T.N| $dot_n"
# The surface-gradient normal equals the TBN-matrix normal for an
# orthonormal frame (Mikkelsen 2019, sec. 2.1); float rounding of the
# derivative and the resolve gives ~1e-5 degrees; 1e-3 degrees is far below
# any visible difference and far above rounding.
awk -v a="$angle" 'BEGIN { exit !(a < 1e-3) }' || fail "bump normal differs from the TBN normal by $angle deg"

step "run engine-integration"
export LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe EGL_PLATFORM=surfaceless
"$work/build-engine-integration/example_engine_integration" -o "$work/engine.png" --size 96x96 \
    >"$work/engine.out" || fail "engine-integration (installed) failed"
grep -qF "wrote $work/engine.png (96x96" "$work/engine.out" || fail "engine-integration: $(cat "$work/engine.out")"
"$engine_in_tree" -o "$work/engine-build-tree.png" --size 96x96 >/dev/null ||
    fail "engine-integration (build tree) failed"
# Same source, same shaders, same llvmpipe: the same bytes.
cmp -s "$work/engine.png" "$work/engine-build-tree.png" ||
    fail "the installed engine-integration's image differs from the build tree's"

# ---- 4. the GLSL library on an engine's include path
step "glslangValidator -I<prefix>/share/surfgrad/shaders"
# -l: link a full stage, the mode in which glslangValidator resolves #include.
glslangValidator -l -I"$prefix/share/surfgrad/shaders" "$src/tests/install/consumer.frag" \
    >"$work/glslang.log" 2>&1 || { cat "$work/glslang.log" >&2; fail "consumer.frag does not validate"; }
if glslangValidator -l "$src/tests/install/consumer.frag" >/dev/null 2>&1; then
    fail "consumer.frag validated without the include path (the test would prove nothing)"
fi
# The same shader in the other dialects (docs/engines.md): GLSL 3.30 core,
# GLSL ES 3.00 (WebGL2) and Vulkan SPIR-V (checked by spirv-val).
for dialect in 330 es300; do
    glslangValidator -l -I"$prefix/share/surfgrad/shaders" \
        "$src/tests/install/consumer_$dialect.frag" >"$work/glslang.log" 2>&1 ||
        { cat "$work/glslang.log" >&2; fail "consumer_$dialect.frag does not validate"; }
done
glslangValidator -V -I"$prefix/share/surfgrad/shaders" "$src/tests/install/consumer_vulkan.frag" \
    -o "$work/consumer.spv" >"$work/glslang.log" 2>&1 ||
    { cat "$work/glslang.log" >&2; fail "consumer_vulkan.frag does not compile to SPIR-V"; }
spirv-val "$work/consumer.spv" || fail "consumer_vulkan.frag: spirv-val rejects the SPIR-V"
# HLSL (Unity, Unreal, D3D): sg/surfgrad.hlsl through glslang's HLSL front
# end (-D), then spirv-val; Metal is SPIRV-Cross's translation of that SPIR-V.
glslangValidator -D -V -S frag -e main -I"$prefix/share/surfgrad/shaders" \
    "$src/tests/install/consumer.hlsl" -o "$work/consumer_hlsl.spv" >"$work/glslang.log" 2>&1 ||
    { cat "$work/glslang.log" >&2; fail "consumer.hlsl does not compile to SPIR-V"; }
spirv-val "$work/consumer_hlsl.spv" || fail "consumer.hlsl: spirv-val rejects the SPIR-V"
spirv-cross --msl "$work/consumer_hlsl.spv" --output "$work/consumer.metal" ||
    fail "consumer.hlsl: SPIRV-Cross cannot write it as Metal"
grep -q "fragment main0_out main0" "$work/consumer.metal" ||
    fail "consumer.metal has no fragment entry point"

# ---- 5. the installed CLI and its data
step "installed surfgrad render share/surfgrad/examples/terrain/scene.json"
cd "$work"
"$prefix/bin/surfgrad" render "$prefix/share/surfgrad/examples/terrain/scene.json" -o terrain.png \
    --size 64x36 >render.out 2>&1 || { cat render.out >&2; fail "rendering the installed terrain example"; }
grep -q "^wrote terrain.png (64x36" render.out || fail "render: $(cat render.out)"
# The installed scenes name the examples' maps through "data:" (not
# "../data/"), so a copy of an installed example elsewhere still renders.
! grep -l '"\.\./data/' "$prefix"/share/surfgrad/examples/*/scene.json ||
    fail "installed example scenes name ../data/ (they break when copied elsewhere)"
mkdir -p "$work/copied"
for ex in terrain tessellated-asset feature-curves; do
    cp "$prefix/share/surfgrad/examples/$ex/scene.json" "$work/copied/$ex.json"
    "$prefix/bin/surfgrad" render "$work/copied/$ex.json" -o "copied-$ex.png" --size 48x32 \
        >"copied-$ex.out" 2>&1 ||
        { cat "copied-$ex.out" >&2; fail "the installed $ex example copied elsewhere does not render"; }
done
# A file only the installation has: "data:" must resolve there, not to the
# source tree this build came from.
mkdir -p "$prefix/share/surfgrad/data/install-test"
cp "$src/examples/data/rock_normal.png" "$prefix/share/surfgrad/data/install-test/only-installed.png"
"$prefix/bin/surfgrad" render "$src/tests/install/sentinel_scene.json" -o sentinel.png \
    >sentinel.out 2>&1 || { cat sentinel.out >&2; fail "data: did not resolve to the installed data"; }
# $SURFGRAD_DATA_DIR overrides: the file is then looked for (and missing) there.
if SURFGRAD_DATA_DIR="$src/data" "$prefix/bin/surfgrad" render "$src/tests/install/sentinel_scene.json" \
    -o sentinel2.png >override.out 2>&1; then
    fail "\$SURFGRAD_DATA_DIR did not override the installed data directory"
fi
grep -qF "$src/data/install-test/only-installed.png: does not exist" override.out ||
    fail "override: $(cat override.out)"
[ ! -e sentinel2.png ] || fail "a failed render left an output file"

# The Python module (when it was built): `import surfgrad` from the moved
# prefix with only its dist-packages folder on PYTHONPATH, and the same
# MikkTSpace vertex count as the installed CLI's for spot.
if [ -n "${SURFGRAD_PYTHON:-}" ]; then
    step "import surfgrad from the installed prefix"
    pydir="$(cd "$prefix" && find . -path '*/dist-packages/surfgrad/__init__.py' | sed 's|^\./||' | head -1)"
    [ -n "$pydir" ] || fail "no lib/python3*/dist-packages/surfgrad/__init__.py in the prefix"
    pydir="$prefix/$(dirname "$(dirname "$pydir")")"
    for f in __init__.pyi normalmap.pyi features.pyi py.typed; do
        [ -f "$pydir/surfgrad/$f" ] || fail "surfgrad/$f not installed"
    done
    py_v="$(PYTHONPATH="$pydir" "$SURFGRAD_PYTHON" -c '
import os, sys, surfgrad
real = os.path.realpath
assert real(surfgrad.__file__).startswith(real(sys.argv[2])), surfgrad.__file__
mesh, added = surfgrad.generate_tangents(surfgrad.load_mesh(sys.argv[1]))
print(mesh.vertex_count, mesh.triangle_count)' "$mesh" "$pydir")" || fail "import surfgrad (installed) failed"
    [ "$py_v" = "$cli_v $cli_t" ] ||
        fail "the installed module's tangents give $py_v vertices/triangles, the CLI's $cli_v $cli_t"
fi
step "passed"
