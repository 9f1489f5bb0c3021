# Script mode (cmake -P), run by the ctest `module_links`: checks the
# module dependency rules of docs/architecture.md ("Layout and dependency
# order") against the configured target graph.
#   LINKS: the file cmake/ModuleLinks.cmake wrote ("<target>|<direct links>"
#          per line);
#   DOC:   docs/architecture.md, whose module-links block must list exactly
#          the direct first-party links of every module.
# A module may link (directly or through another target) only the modules
# listed for it below; tests, fuzzers and benchmarks of mesh/ must not pull
# in the modules above it. Fails naming every offending edge.

cmake_minimum_required(VERSION 3.20) # IN_LIST, list(POP_FRONT)

# Module -> the first-party targets it may reach by linking.
set(_modules surfgrad_shaders surfgrad_base surfgrad_bump surfgrad_features surfgrad_mesh
             surfgrad_gl surfgrad_parity surfgrad_render surfgrad_viewer surfgrad_normalmap
             surfgrad_image surfgrad_bake surfgrad_translate surfgrad_python)
set(_may_surfgrad_shaders "")
set(_may_surfgrad_base "")
set(_may_surfgrad_bump surfgrad_shaders surfgrad_base)
# Feature maps read and write their EXR files through the image module.
set(_may_surfgrad_features surfgrad_bump surfgrad_image surfgrad_shaders surfgrad_base)
set(_may_surfgrad_mesh surfgrad_base)
# The image type, reader and writer: base, glm and OpenImageIO, nothing else.
set(_may_surfgrad_image surfgrad_base)
set(_may_surfgrad_gl surfgrad_shaders surfgrad_base)
set(_may_surfgrad_parity surfgrad_bump surfgrad_gl surfgrad_shaders surfgrad_base)
set(_may_surfgrad_render surfgrad_bump surfgrad_features surfgrad_mesh surfgrad_gl
                         surfgrad_image surfgrad_shaders surfgrad_base)
set(_may_surfgrad_viewer surfgrad_render ${_may_surfgrad_render})
# Image operations: the shared math (bump) and the mesh's tangent frames; no
# GL, no renderer, no feature curves.
set(_may_surfgrad_normalmap surfgrad_bump surfgrad_mesh surfgrad_image surfgrad_shaders
                            surfgrad_base)
# The baker: the normal-map grids and frames, the mesh's patch tables, the
# shared patch bases; no GL, no renderer.
set(_may_surfgrad_bake surfgrad_normalmap ${_may_surfgrad_normalmap})
# Shader targets: programs in, programs out; the renderer does not link it.
set(_may_surfgrad_translate surfgrad_shaders surfgrad_base)
# The Python module binds the libraries users call (not the viewer, not
# the parity harness).
set(_may_surfgrad_python surfgrad_render surfgrad_normalmap surfgrad_bake ${_may_surfgrad_render})
# Executables that exercise one module: what they must not reach.
set(_mesh_only_regex "^(fuzz_mesh_|fuzz_mikktspace|mesh_tests|mesh_tangents_tests|mesh_bench$|tangents_bench$)")
set(_mesh_only_forbidden surfgrad_features surfgrad_bump surfgrad_gl surfgrad_parity surfgrad_image
                         surfgrad_render surfgrad_viewer)
set(_base_regex "^base_")
set(_base_forbidden surfgrad_shaders surfgrad_bump surfgrad_features surfgrad_mesh surfgrad_gl surfgrad_image
                    surfgrad_parity surfgrad_render surfgrad_viewer)

if(NOT EXISTS "${LINKS}")
    message(FATAL_ERROR "module_links: ${LINKS} does not exist (re-run CMake)")
endif()
file(STRINGS "${LINKS}" _lines)
set(_targets "")
set(_not_configured "") # optional modules this build left out
foreach(_line IN LISTS _lines)
    string(FIND "${_line}" "|" _bar)
    string(SUBSTRING "${_line}" 0 ${_bar} _t)
    math(EXPR _from "${_bar} + 1")
    string(SUBSTRING "${_line}" ${_from} -1 _deps)
    if(_deps STREQUAL "#not-configured")
        list(APPEND _not_configured ${_t})
        continue()
    endif()
    # Generator expressions LINK_LIBRARIES keeps unevaluated: a target named
    # conditionally counts as linked.
    string(REGEX REPLACE "\\$<(TARGET_NAME_IF_EXISTS|LINK_ONLY|BUILD_INTERFACE):([^>]*)>" "\\2"
           _deps "${_deps}")
    list(APPEND _targets ${_t})
    set(_direct_${_t} ${_deps})
endforeach()

# Direct first-party links of every target.
foreach(_t IN LISTS _targets)
    set(_own_${_t} "")
    foreach(_d IN LISTS _direct_${_t})
        if(_d IN_LIST _targets)
            list(APPEND _own_${_t} ${_d})
        endif()
    endforeach()
    list(REMOVE_DUPLICATES _own_${_t})
    list(SORT _own_${_t})
endforeach()

# Everything a target reaches through first-party links, with the path.
function(_reach t out)
    set(_seen "")
    set(_todo ${t})
    set(_via_${t} "${t}")
    while(_todo)
        list(POP_FRONT _todo _cur)
        foreach(_d IN LISTS _own_${_cur})
            if(NOT _d IN_LIST _seen)
                list(APPEND _seen ${_d})
                list(APPEND _todo ${_d})
                set(_via_${_d} "${_via_${_cur}} -> ${_d}")
                set(_path_${_d} "${_via_${_cur}} -> ${_d}" PARENT_SCOPE)
            endif()
        endforeach()
    endwhile()
    set(${out} ${_seen} PARENT_SCOPE)
endfunction()

set(_errors "")
foreach(_m IN LISTS _modules)
    if(NOT _m IN_LIST _targets)
        continue() # optional module not configured (e.g. the viewer)
    endif()
    _reach(${_m} _reached)
    foreach(_d IN LISTS _reached)
        if(NOT _d IN_LIST _may_${_m})
            string(APPEND _errors "  ${_m} must not link ${_d} (${_path_${_d}})\n")
        endif()
    endforeach()
endforeach()
foreach(_t IN LISTS _targets)
    foreach(_kind mesh_only base)
        if(_t MATCHES "${_${_kind}_regex}")
            _reach(${_t} _reached)
            foreach(_d IN LISTS _reached)
                if(_d IN_LIST _${_kind}_forbidden)
                    string(APPEND _errors "  ${_t} must not link ${_d} (${_path_${_d}})\n")
                endif()
            endforeach()
        endif()
    endforeach()
endforeach()

# The graph as docs/architecture.md writes it: between the markers, one
# line per module, "<module> -> <direct first-party links, sorted>" or
# "<module> -> (none)".
if(DOC)
    file(READ "${DOC}" _doc)
    string(FIND "${_doc}" "<!-- module-links:begin -->" _b)
    string(FIND "${_doc}" "<!-- module-links:end -->" _e)
    if(_b EQUAL -1 OR _e EQUAL -1)
        string(APPEND _errors "  ${DOC}: no module-links block\n")
    else()
        string(SUBSTRING "${_doc}" ${_b} -1 _block)
        math(EXPR _len "${_e} - ${_b}")
        string(SUBSTRING "${_doc}" ${_b} ${_len} _block)
        string(REPLACE "\n" ";" _doc_lines "${_block}")
        set(_documented "")
        foreach(_line IN LISTS _doc_lines)
            if(_line MATCHES "^(surfgrad[_a-z]*) +-> +(.*)$")
                set(_m "${CMAKE_MATCH_1}")
                string(STRIP "${CMAKE_MATCH_2}" _said)
                set(_rhs "${_said}")
                list(APPEND _documented ${_m})
                if(_rhs STREQUAL "(none)")
                    set(_rhs "")
                endif()
                string(REGEX REPLACE " +" ";" _rhs "${_rhs}")
                list(SORT _rhs)
                if(_m IN_LIST _not_configured)
                    # documented, but this configuration does not build it
                elseif(NOT _m IN_LIST _targets)
                    string(APPEND _errors "  ${DOC}: ${_m} is not a target\n")
                elseif(NOT "${_rhs}" STREQUAL "${_own_${_m}}")
                    string(REPLACE ";" " " _want "${_own_${_m}}")
                    string(APPEND _errors
                           "  ${DOC}: ${_m} links \"${_want}\" in CMake, the page says \"${_said}\"\n")
                endif()
            endif()
        endforeach()
        foreach(_m IN LISTS _modules ITEMS surfgrad)
            if(_m IN_LIST _targets AND NOT _m IN_LIST _documented)
                string(APPEND _errors "  ${DOC}: module ${_m} missing from the module-links block\n")
            endif()
        endforeach()
    endif()
endif()

if(_errors)
    message(FATAL_ERROR "module_links: forbidden or undocumented links:\n${_errors}")
endif()
list(LENGTH _targets _n)
message(STATUS "module_links: ${_n} targets follow the module rules and the documented graph")
