# FindOpenSubdiv: Debian's OpenSubdivConfig.cmake names static libraries the
# package does not ship, so find_package(OpenSubdiv CONFIG) fails. This module
# finds the headers and the two shared libraries and makes imported targets:
#   OpenSubdiv::osdCPU  (Sdc/Vtr/Far/Bfr + CPU evaluators; links libgomp)
#   OpenSubdiv::osdGPU  (GL evaluators and patch shader source only)
# and sets OpenSubdiv_VERSION from opensubdiv/version.h.
find_path(OpenSubdiv_INCLUDE_DIR NAMES opensubdiv/version.h)
find_library(OpenSubdiv_osdCPU_LIBRARY NAMES osdCPU)
find_library(OpenSubdiv_osdGPU_LIBRARY NAMES osdGPU)

if(OpenSubdiv_INCLUDE_DIR AND EXISTS "${OpenSubdiv_INCLUDE_DIR}/opensubdiv/version.h")
    file(STRINGS "${OpenSubdiv_INCLUDE_DIR}/opensubdiv/version.h" _osd_ver
         REGEX "#define OPENSUBDIV_VERSION_(MAJOR|MINOR|PATCH) ")
    foreach(_part MAJOR MINOR PATCH)
        string(REGEX REPLACE ".*#define OPENSUBDIV_VERSION_${_part} ([0-9]+).*" "\\1"
               _osd_${_part} "${_osd_ver}")
    endforeach()
    set(OpenSubdiv_VERSION "${_osd_MAJOR}.${_osd_MINOR}.${_osd_PATCH}")
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenSubdiv
    REQUIRED_VARS OpenSubdiv_INCLUDE_DIR OpenSubdiv_osdCPU_LIBRARY
    VERSION_VAR OpenSubdiv_VERSION)

if(OpenSubdiv_FOUND AND NOT TARGET OpenSubdiv::osdCPU)
    add_library(OpenSubdiv::osdCPU SHARED IMPORTED)
    set_target_properties(OpenSubdiv::osdCPU PROPERTIES
        IMPORTED_LOCATION "${OpenSubdiv_osdCPU_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenSubdiv_INCLUDE_DIR}")
    if(OpenSubdiv_osdGPU_LIBRARY)
        add_library(OpenSubdiv::osdGPU SHARED IMPORTED)
        set_target_properties(OpenSubdiv::osdGPU PROPERTIES
            IMPORTED_LOCATION "${OpenSubdiv_osdGPU_LIBRARY}"
            INTERFACE_INCLUDE_DIRECTORIES "${OpenSubdiv_INCLUDE_DIR}"
            INTERFACE_LINK_LIBRARIES OpenSubdiv::osdCPU)
    endif()
endif()
mark_as_advanced(OpenSubdiv_INCLUDE_DIR OpenSubdiv_osdCPU_LIBRARY OpenSubdiv_osdGPU_LIBRARY)
