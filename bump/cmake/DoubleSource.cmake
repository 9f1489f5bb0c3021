# Script mode (cmake -P): writes a double-precision copy of the shared shader
# math for the parity suite's reference evaluation (bump/src/eval_double.cpp).
# The copy is the SAME formulas with the float-literal suffixes removed
# (1.0f -> 1.0) and `#include "sg/...` redirected to `sgd/...`; the including
# C++ file maps vec*/mat* to GLM's dvec*/dmat* and `float` to `double`.
# SHADER_ROOT: shaders/; OUTPUT_DIR: where sgd/ is written; FILES: paths
# relative to SHADER_ROOT/sg (';'-separated).
foreach(_f IN LISTS FILES)
    file(READ "${SHADER_ROOT}/sg/${_f}" _text)
    # A float literal is a digit (or '.') followed by 'f' and a non-identifier
    # character; identifiers in the shared code never end in <digit>f.
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
