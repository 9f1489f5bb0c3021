# All third-party packages, found once. Installed on Debian 12 by
# scripts/setup-deps (see README). Quirks handled here are documented in
# docs/platform.md.
find_package(glm REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(CLI11 REQUIRED)
find_package(OpenMesh REQUIRED)
find_package(OpenSubdiv REQUIRED)          # cmake/FindOpenSubdiv.cmake
find_package(TinyGLTF REQUIRED)
find_package(Freetype REQUIRED)
find_package(TBB REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET epoxy)
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)

# OpenImageIO's exported target names /usr/include/opencv4, which does not
# exist unless libopencv-dev is installed; CMake then fails at generate time.
find_package(OpenImageIO REQUIRED)
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

if(SURFGRAD_BUILD_VIEWER)
    find_package(glfw3 REQUIRED)
    pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
endif()
if(SURFGRAD_BUILD_TESTS)
    find_package(GTest REQUIRED)
endif()
if(SURFGRAD_BUILD_BENCH)
    find_package(benchmark REQUIRED)
endif()
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
