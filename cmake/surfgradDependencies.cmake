# The third-party packages the surfgrad libraries link, found in one place
# for two callers:
#  - the build (cmake/SurfgradDeps.cmake includes this file): a missing
#    package is a configure error;
#  - the installed package (surfgradConfig.cmake includes its installed
#    copy with _surfgrad_in_config set): the libraries are static, so a
#    consumer links their private dependencies too; a missing package makes
#    find_package(surfgrad) fail naming it (find_dependency), and the
#    including config returns.
# The Debian quirks handled here are in docs/platform.md ("CMake quirks").
# Input: _surfgrad_with_viewer (the viewer library is built / installed).
include(CMakeFindDependencyMacro)

# find_package(<args> REQUIRED) in the build, find_dependency(<args>) in the
# installed config (a macro, so that find_dependency's return() leaves this
# file when a package is missing).
macro(_surfgrad_find_dependency)
    if(_surfgrad_in_config)
        find_dependency(${ARGN})
    else()
        find_package(${ARGN} REQUIRED)
    endif()
endmacro()

# pkg-config modules, as the imported targets PkgConfig::<PREFIX> the
# libraries name (already made by the consumer: kept).
macro(_surfgrad_pkg_dependency prefix module)
    if(NOT TARGET PkgConfig::${prefix})
        if(_surfgrad_in_config)
            pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
            if(NOT ${prefix}_FOUND)
                set(surfgrad_NOT_FOUND_MESSAGE
                    "surfgrad could not be found because pkg-config module ${module} was not found.")
                set(surfgrad_FOUND FALSE)
                return()
            endif()
        else()
            pkg_check_modules(${prefix} REQUIRED IMPORTED_TARGET ${module})
        endif()
    endif()
endmacro()

# OpenImageIO's exported target names /usr/include/opencv4, which does not
# exist unless libopencv-dev is installed; CMake then fails at generate
# time. The directory is filtered out of its include directories.
function(_surfgrad_fix_openimageio_targets)
    foreach(_oiio_tgt OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
        if(TARGET ${_oiio_tgt})
            foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
                get_target_property(_dirs ${_oiio_tgt} ${_prop})
                if(_dirs)
                    list(FILTER _dirs EXCLUDE REGEX "opencv4")
                    set_target_properties(${_oiio_tgt} PROPERTIES ${_prop} "${_dirs}")
                endif()
            endforeach()
        endif()
    endforeach()
endfunction()

_surfgrad_find_dependency(glm)                 # shaders, bump, image, mesh, render headers
_surfgrad_find_dependency(nlohmann_json)
_surfgrad_find_dependency(OpenMesh)            # mesh: surfgrad/mesh/polymesh.h (OpenMeshCore)
# Debian's OpenSubdivConfig.cmake is broken: FindOpenSubdiv.cmake (beside
# this file, on CMAKE_MODULE_PATH) makes OpenSubdiv::osdCPU.
_surfgrad_find_dependency(OpenSubdiv)
_surfgrad_find_dependency(TinyGLTF)
_surfgrad_find_dependency(Freetype)
_surfgrad_find_dependency(pugixml 1.11)       # features: the XML of SVG input (pugixml::pugixml)
_surfgrad_find_dependency(TBB)
_surfgrad_find_dependency(embree 3)          # bake: ray casting (target embree)
_surfgrad_find_dependency(OpenImageIO)
_surfgrad_fix_openimageio_targets()
_surfgrad_find_dependency(PkgConfig)
_surfgrad_pkg_dependency(EPOXY epoxy)
_surfgrad_pkg_dependency(EGL egl)
# translate: shader targets (glslang's GLSL/HLSL front ends and SPIR-V
# generation, the SPIR-V validator, SPIRV-Cross's C API).
# Debian's glslang config names Threads::Threads without finding it.
_surfgrad_find_dependency(Threads)
_surfgrad_find_dependency(glslang)
_surfgrad_find_dependency(SPIRV-Tools)
_surfgrad_pkg_dependency(SPIRV_CROSS_C spirv-cross-c-shared)
if(_surfgrad_with_viewer)
    _surfgrad_find_dependency(glfw3)
    _surfgrad_pkg_dependency(IMGUI imgui)
endif()
