# SPDX-License-Identifier: Apache-2.0
# Installation (cmake --install) and packaging (cpack -G DEB). Layout under
# the prefix (directories set in the top-level CMakeLists.txt):
#   bin/surfgrad                          the CLI                    [runtime]
#   share/man/man1/surfgrad.1.gz          its manual page, generated from
#                                         the help texts at build time [runtime]
#   share/doc/surfgrad/copyright          licenses: the project's and every
#                                         bundled data set's (Debian format) [runtime]
#   share/doc/surfgrad/LICENSE            the Apache License 2.0     [runtime]
#   share/doc/surfgrad-dev/copyright      the same, for surfgrad-dev [development]
#   share/surfgrad/data/                  data/ ("data:" in scenes)  [runtime]
#   share/surfgrad/examples/              examples/                  [runtime]
#   include/surfgrad/<module>/*.h         public headers of each module   [development]
#   include/surfgrad/<module>.h           its umbrella header             [development]
#   lib/libsurfgrad_*.a                   the libraries, static          [development]
#   lib/cmake/surfgrad/                   surfgradConfig.cmake, version, targets,
#                                         surfgradDependencies.cmake,
#                                         FindOpenSubdiv.cmake           [development]
#   share/surfgrad/shaders/sg/**.glsl     the GLSL library               [development]
# The two components become the Debian packages surfgrad and surfgrad-dev;
# `cmake --install` installs both. docs/install.md describes the use.
include(CMakePackageConfigHelpers)
set(SURFGRAD_INSTALL_EXAMPLESDIR "${SURFGRAD_INSTALL_SHAREDIR}/examples")

# ---- libraries, headers, the CLI
get_property(_sg_targets GLOBAL PROPERTY SURFGRAD_EXPORTED_TARGETS)
install(TARGETS ${_sg_targets} EXPORT surfgradTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT development
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT development)
get_property(_sg_header_dirs GLOBAL PROPERTY SURFGRAD_HEADER_DIRS)
foreach(_dir IN LISTS _sg_header_dirs)
    install(DIRECTORY "${_dir}/" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
            COMPONENT development FILES_MATCHING PATTERN "*.h")
endforeach()
set_target_properties(surfgrad PROPERTIES EXPORT_NAME surfgrad)
install(TARGETS surfgrad EXPORT surfgradTargets
        RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT runtime)

# ---- the manual page, from the help texts of the program just built
# (cmake/ManPage.cmake walks every command's --help), and the licenses.
find_program(SURFGRAD_GZIP gzip)
mark_as_advanced(SURFGRAD_GZIP)
if(SURFGRAD_GZIP)
    set(_sg_man "${PROJECT_BINARY_DIR}/man/surfgrad.1.gz")
else()
    set(_sg_man "${PROJECT_BINARY_DIR}/man/surfgrad.1")
endif()
add_custom_command(
    OUTPUT "${_sg_man}"
    COMMAND "${CMAKE_COMMAND}" -DSURFGRAD=$<TARGET_FILE:surfgrad> -DVERSION=${PROJECT_VERSION}
            -DOUT=${_sg_man} -DGZIP=${SURFGRAD_GZIP} -P "${PROJECT_SOURCE_DIR}/cmake/ManPage.cmake"
    DEPENDS surfgrad "${PROJECT_SOURCE_DIR}/cmake/ManPage.cmake"
    COMMENT "Generating the manual page surfgrad(1) from the help texts"
    VERBATIM)
add_custom_target(surfgrad_man ALL DEPENDS "${_sg_man}")
install(FILES "${_sg_man}" DESTINATION "${CMAKE_INSTALL_MANDIR}/man1" COMPONENT runtime)
install(FILES "${PROJECT_SOURCE_DIR}/packaging/copyright" "${PROJECT_SOURCE_DIR}/LICENSE"
        DESTINATION "${CMAKE_INSTALL_DATAROOTDIR}/doc/surfgrad" COMPONENT runtime)
install(FILES "${PROJECT_SOURCE_DIR}/packaging/copyright"
        DESTINATION "${CMAKE_INSTALL_DATAROOTDIR}/doc/surfgrad-dev" COMPONENT development)

# ---- the shader library: share/surfgrad/shaders/sg/**.glsl and its HLSL
# entries (**.hlsl), so that `#include "sg/surfgrad.glsl"` (GLSL) and
# `#include "sg/surfgrad.hlsl"` (HLSL) resolve with only
# share/surfgrad/shaders on the include path (and C++ sees the same files
# through surfgrad::shaders).
install(DIRECTORY "${PROJECT_SOURCE_DIR}/shaders/sg" DESTINATION "${SURFGRAD_INSTALL_SHADERDIR}"
        COMPONENT development FILES_MATCHING PATTERN "*.glsl" PATTERN "*.hlsl")
# ... and as one file per language (shaders/flat, written by the build).
install(FILES "${SURFGRAD_FLAT_DIR}/surfgrad.glsl" "${SURFGRAD_FLAT_DIR}/surfgrad.hlsl"
              "${SURFGRAD_FLAT_DIR}/surfgrad.ush"
        DESTINATION "${SURFGRAD_INSTALL_SHADERDIR}/flat" COMPONENT development)

# ---- data and examples: the installed `surfgrad render
# share/surfgrad/examples/terrain/scene.json` finds "../data/..." beside it
# and "data:..." in share/surfgrad/data (sg::render::dataDirectory()).
install(DIRECTORY "${PROJECT_SOURCE_DIR}/data/" DESTINATION "${SURFGRAD_INSTALL_DATADIR}"
        COMPONENT runtime)
install(DIRECTORY "${PROJECT_SOURCE_DIR}/examples/" DESTINATION "${SURFGRAD_INSTALL_EXAMPLESDIR}"
        COMPONENT runtime USE_SOURCE_PERMISSIONS
        # examples/CMakeLists.txt only adds the sample programs to this build;
        # each program's own CMakeLists.txt also builds it on its own.
        REGEX "/examples/CMakeLists\\.txt$" EXCLUDE
        # the three.js example's npm packages: `npm ci` makes them (README)
        PATTERN "node_modules" EXCLUDE)
# The installed scenes name their maps "data:../examples/data/..." instead
# of "../data/...": "data:" resolves to the installation's data directory
# (beside which the examples' own maps are installed), so a scene copied
# out of the installation still finds them; in the source tree "../data/"
# stays (the examples' own folder, readable without an installation).
string(CONFIGURE [[
    set(_sg_ex "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/@SURFGRAD_INSTALL_EXAMPLESDIR@")
    file(GLOB _sg_scenes "${_sg_ex}/*/scene.json")
    foreach(_f IN LISTS _sg_scenes)
        file(READ "${_f}" _text)
        string(REPLACE "\"../data/" "\"data:../examples/data/" _new "${_text}")
        if(NOT _new STREQUAL _text)
            file(WRITE "${_f}.tmp" "${_new}")
            file(RENAME "${_f}.tmp" "${_f}")
        endif()
    endforeach()
]] _sg_rewrite_scenes @ONLY)
install(CODE "${_sg_rewrite_scenes}" COMPONENT runtime)

# ---- the package config: find_package(surfgrad CONFIG REQUIRED)
install(EXPORT surfgradTargets NAMESPACE surfgrad:: DESTINATION "${SURFGRAD_INSTALL_CMAKEDIR}"
        COMPONENT development)
configure_package_config_file(
    "${PROJECT_SOURCE_DIR}/cmake/surfgradConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/cmake/surfgradConfig.cmake"
    INSTALL_DESTINATION "${SURFGRAD_INSTALL_CMAKEDIR}"
    PATH_VARS SURFGRAD_INSTALL_SHADERDIR SURFGRAD_INSTALL_DATADIR SURFGRAD_INSTALL_EXAMPLESDIR)
# 0.x: a minor version may change the API, so only the same major.minor matches.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/cmake/surfgradConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/cmake/surfgradConfig.cmake"
              "${PROJECT_BINARY_DIR}/cmake/surfgradConfigVersion.cmake"
              "${PROJECT_SOURCE_DIR}/cmake/surfgradDependencies.cmake"
              "${PROJECT_SOURCE_DIR}/cmake/FindOpenSubdiv.cmake"
        DESTINATION "${SURFGRAD_INSTALL_CMAKEDIR}" COMPONENT development)

# ---- Debian packages: cpack -G DEB (in the build directory) writes
#   surfgrad_<version>_<arch>.deb      the CLI, data, examples; Depends from
#                                      dpkg-shlibdeps plus GLVND's EGL/GL and
#                                      Mesa's drivers (loaded at run time, so
#                                      shlibdeps cannot see them);
#   surfgrad-dev_<version>_<arch>.deb  headers, static libraries, CMake
#                                      config, GLSL library; Depends on
#                                      surfgrad and the -dev packages whose
#                                      CMake targets the config finds.
# tests/install/package_test.sh checks both; scripts/test-package installs
# them on a clean Debian 12 root and renders.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME surfgrad)
set(CPACK_PACKAGE_VENDOR "surfgrad")
# The project's license, SPDX identifier; the data sets' licenses are in
# share/doc/surfgrad/copyright (packaging/copyright).
set(SURFGRAD_LICENSE "Apache-2.0")
set(SURFGRAD_DATA_LICENSES "CC0-1.0, CC-BY-4.0, ISC, public domain and OpenSubdiv's modified Apache-2.0")
set(CPACK_RESOURCE_FILE_LICENSE "${PROJECT_SOURCE_DIR}/LICENSE")
# The Maintainer field: whoever builds the packages sets it (the default's
# .invalid domain, RFC 2606, is a placeholder that cannot receive mail).
set(SURFGRAD_PACKAGE_MAINTAINER "surfgrad maintainers <maintainers@surfgrad.invalid>"
    CACHE STRING "Maintainer field of the Debian packages (name <email>)")
set(CPACK_PACKAGE_CONTACT "${SURFGRAD_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL runtime development)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME surfgrad)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# libepoxy dlopens libEGL.so.1 and libGL.so.1 (GLVND), which load Mesa's
# EGL vendor library and llvmpipe: none of them is seen by dpkg-shlibdeps.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "libegl1, libgl1, libegl-mesa0, libgl1-mesa-dri")
# The feature-curves example renders glyphs of DejaVu Serif.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "fonts-dejavu-core")
# Descriptions: the first line is the synopsis.
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION "surface-gradient bump mapping on subdivision meshes (CLI)
surfgrad renders bump-mapped subdivision meshes with surface gradients
(Mikkelsen 2019): normal, height, triplanar, decal, noise and feature-curve
layers add as surface gradients. This package holds the surfgrad command
(render, shader, view, mesh, features, eval, selftest), the example scenes
and the data they read (/usr/share/surfgrad).
.
License: ${SURFGRAD_LICENSE}; bundled data: ${SURFGRAD_DATA_LICENSES}
(/usr/share/doc/surfgrad/copyright).")
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME surfgrad-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEVELOPMENT_DESCRIPTION "surface-gradient bump mapping on subdivision meshes (development)
Headers, static libraries and the CMake package of surfgrad, for
find_package(surfgrad CONFIG REQUIRED) and the targets surfgrad::bump,
surfgrad::mesh, surfgrad::features, surfgrad::render, surfgrad::bake and the
others; the
GLSL library for engines under /usr/share/surfgrad/shaders (sg/*.glsl).
.
License: ${SURFGRAD_LICENSE} (/usr/share/doc/surfgrad-dev/copyright).")
# openimageio-tools: Debian's OpenImageIOConfig.cmake fails unless the
# tools it exports as targets (/usr/bin/iconvert, ...) are installed.
set(_sg_dev_depends
    "surfgrad (= ${PROJECT_VERSION})" cmake pkg-config libglm-dev nlohmann-json3-dev
    libopenmesh-dev libosd-dev libtinygltf-dev libfreetype-dev libpugixml-dev libtbb-dev
    libembree-dev libopenimageio-dev openimageio-tools libepoxy-dev libegl-dev
    glslang-dev spirv-tools libspirv-cross-c-shared-dev)
if(SURFGRAD_BUILD_VIEWER)
    list(APPEND _sg_dev_depends libglfw3-dev libimgui-dev)
endif()
string(REPLACE ";" ", " CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS "${_sg_dev_depends}")
# python3-surfgrad: the Python module (python/CMakeLists.txt installs it in
# /usr/lib/python3/dist-packages/surfgrad). Built for one Python minor
# version (the extension's ABI); the scenes' "data:" paths resolve to the
# surfgrad package's /usr/share/surfgrad/data.
if(SURFGRAD_PYTHON_BUILT)
    install(FILES "${PROJECT_SOURCE_DIR}/packaging/copyright"
            DESTINATION "${CMAKE_INSTALL_DATAROOTDIR}/doc/python3-surfgrad" COMPONENT python)
    list(APPEND CPACK_COMPONENTS_ALL python)
    set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-surfgrad)
    set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
    set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS ON)
    set(_sg_pymaj ${SURFGRAD_PYTHON_VERSION_MAJOR})
    set(_sg_pymin ${SURFGRAD_PYTHON_VERSION_MINOR})
    math(EXPR _sg_pynext "${_sg_pymin} + 1")
    set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
        "surfgrad (= ${PROJECT_VERSION}), python3 (>= ${_sg_pymaj}.${_sg_pymin}), python3 (<< ${_sg_pymaj}.${_sg_pynext}), python3-numpy, libegl1, libgl1, libegl-mesa0, libgl1-mesa-dri")
    set(CPACK_DEBIAN_PYTHON_DESCRIPTION "surface-gradient bump mapping on subdivision meshes (Python module)
The Python module surfgrad: MikkTSpace-exact and limit tangents, OpenSubdiv
subdivision with limit frames and animated cages, blendshapes, the
height-field-correct normal-map operations, feature-curve bakes, headless
rendering and the shared shader functions, on numpy arrays.
.
License: ${SURFGRAD_LICENSE} (/usr/share/doc/surfgrad/copyright).")
endif()
include(CPack)
