# Binary64 copies of the shared shader source (shaders/sg/**.glsl) for the
# reference evaluations compiled in double precision through
# shaders/include/surfgrad/shaders/glsl_cpp_double.h (bump/src/eval_double.cpp,
# features/src/shared_double.cpp). A copy is the SAME formulas with the
# float-literal suffixes removed (1.0f -> 1.0) and `#include "sg/...`
# redirected to `sgd/...`; the including C++ file maps the GLSL float types
# to double (glsl_cpp_double.h).
#
# surfgrad_double_sources(target FILES file...): writes, at build time, the
# copy of each FILES path (relative to shaders/sg; every file the copies
# include must be listed too) to <current binary dir>/double/sgd/<path>,
# makes them sources of `target` and puts <current binary dir>/double on its
# private include path, so `#include "sgd/<path>"` finds them. A copy is
# rewritten only when its text changes.
#
# This file is also the script that writes the copies (cmake -P, with
# SHADER_ROOT: shaders/; OUTPUT_DIR: where sgd/ goes; FILES: the paths,
# ';'-separated).
if(CMAKE_SCRIPT_MODE_FILE)
    foreach(_f IN LISTS FILES)
        file(READ "${SHADER_ROOT}/sg/${_f}" _text)
        # A float literal is a digit (or '.') followed by 'f' and a
        # non-identifier character; identifiers in the shared code never
        # end in <digit>f.
        string(REGEX REPLACE "([0-9.])f([^A-Za-z0-9_])" "\\1\\2" _text "${_text}")
        string(REPLACE "#include \"sg/" "#include \"sgd/" _text "${_text}")
        set(_out "${OUTPUT_DIR}/sgd/${_f}")
        set(_old "")
        if(EXISTS "${_out}")
            file(READ "${_out}" _old)
        endif()
        if(NOT "${_old}" STREQUAL "${_text}")
            file(WRITE "${_out}" "${_text}")
        endif()
    endforeach()
    return()
endif()

function(surfgrad_double_sources tgt)
    cmake_parse_arguments(D "" "" "FILES" ${ARGN})
    if(NOT D_FILES OR D_UNPARSED_ARGUMENTS)
        message(FATAL_ERROR "surfgrad_double_sources(${tgt} FILES file...): "
                            "unexpected '${D_UNPARSED_ARGUMENTS}' or no FILES")
    endif()
    set(dir "${CMAKE_CURRENT_BINARY_DIR}/double")
    set(script "${CMAKE_CURRENT_FUNCTION_LIST_FILE}")
    set(out "")
    set(in "")
    foreach(f IN LISTS D_FILES)
        list(APPEND out "${dir}/sgd/${f}")
        list(APPEND in "${PROJECT_SOURCE_DIR}/shaders/sg/${f}")
    endforeach()
    string(REPLACE ";" "\\;" arg "${D_FILES}")
    add_custom_command(
        OUTPUT ${out}
        COMMAND ${CMAKE_COMMAND} -DSHADER_ROOT=${PROJECT_SOURCE_DIR}/shaders
                -DOUTPUT_DIR=${dir} "-DFILES=${arg}" -P ${script}
        DEPENDS ${in} ${script}
        COMMENT "Generating the double-precision copy of the shader source of ${tgt}")
    target_sources(${tgt} PRIVATE ${out})
    target_include_directories(${tgt} PRIVATE ${dir})
endfunction()
