# surfgrad_write_module_links(OUTPUT file): at generate time, writes one line
# per target of the project, "<target>|<its LINK_LIBRARIES>" (the direct
# links, PUBLIC and PRIVATE, generator expressions evaluated). The ctest
# module_links (cmake/CheckModuleLinks.cmake) reads it to enforce the
# module dependency rules and to compare the graph with docs/architecture.md.
# OPTIONAL names modules a configuration may leave out (the Python module in
# a sanitizer build, the viewer without GLFW): each one that is not a target
# here gets the line "<module>|#not-configured", so the check can tell a
# module this build skipped from a name the page invented.
# DIRS (optional) names a second file with one line per target,
# "<target>|<its source folder>", for the ctest module_includes
# (tests/architecture/module_includes.py), which checks the folders.
function(_surfgrad_collect_targets dir out)
    get_property(_targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
    get_property(_subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
    foreach(_sub IN LISTS _subdirs)
        _surfgrad_collect_targets("${_sub}" _more)
        list(APPEND _targets ${_more})
    endforeach()
    set(${out} ${_targets} PARENT_SCOPE)
endfunction()

function(surfgrad_write_module_links)
    cmake_parse_arguments(M "" "OUTPUT;DIRS" "OPTIONAL" ${ARGN})
    _surfgrad_collect_targets("${PROJECT_SOURCE_DIR}" _all)
    set(_content "")
    set(_dirs "")
    foreach(_t IN LISTS M_OPTIONAL)
        if(NOT _t IN_LIST _all)
            string(APPEND _content "${_t}|#not-configured\n")
        endif()
    endforeach()
    foreach(_t IN LISTS _all)
        get_target_property(_type ${_t} TYPE)
        if(_type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|MODULE_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$")
            string(APPEND _content "${_t}|$<JOIN:$<TARGET_PROPERTY:${_t},LINK_LIBRARIES>,;>\n")
            get_target_property(_dir ${_t} SOURCE_DIR)
            string(APPEND _dirs "${_t}|${_dir}\n")
        endif()
    endforeach()
    file(GENERATE OUTPUT "${M_OUTPUT}" CONTENT "${_content}")
    if(M_DIRS)
        file(WRITE "${M_DIRS}" "${_dirs}")
    endif()
endfunction()
