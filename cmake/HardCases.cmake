# docs/hard-cases.md from the hard-case reports of the tests.
#   cmake -DBUILD_DIR=<build> -DSOURCE_DIR=<source> -DMODE=generate|check
#         [-DCTEST=<ctest>] -P cmake/HardCases.cmake
# Reads the tests labelled `hardcase` in BUILD_DIR (ctest -N -L), the rows
# each reported into BUILD_DIR/hardcases/<test>.jsonl when it last ran
# (tests/common/hardcase.h), and the families of
# SOURCE_DIR/tests/hardcase_families.txt. MODE=generate writes
# SOURCE_DIR/docs/hard-cases.md; MODE=check (the ctest hard_cases_doc)
# fails, saying what differs, when that file is not what generate would
# write, comparing every cell except the measured values of rows a test
# marked machine-dependent. Also fails when a labelled test has no report,
# a report names an unknown family, or a test that is not labelled reports.
cmake_minimum_required(VERSION 3.20)
foreach(_v BUILD_DIR SOURCE_DIR MODE)
    if(NOT DEFINED ${_v})
        message(FATAL_ERROR "HardCases.cmake: -D${_v}=... is required")
    endif()
endforeach()
if(NOT CTEST)
    set(CTEST ctest)
endif()
set(_doc "${SOURCE_DIR}/docs/hard-cases.md")
set(_reports "${BUILD_DIR}/hardcases")
set(_errors "")

# Test names from `ctest -N` output ("  Test  #12: Name").
function(_ctest_names out)
    execute_process(COMMAND ${CTEST} -N ${ARGN} WORKING_DIRECTORY "${BUILD_DIR}"
                    OUTPUT_VARIABLE _text RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0)
        message(FATAL_ERROR "HardCases.cmake: ctest -N ${ARGN} failed in ${BUILD_DIR}")
    endif()
    string(REGEX MATCHALL "Test +#[0-9]+: [^\n]+" _lines "${_text}")
    set(_names "")
    foreach(_l IN LISTS _lines)
        string(REGEX REPLACE "^Test +#[0-9]+: " "" _n "${_l}")
        # gtest_discover_tests names a value-parameterised case
        # "Suite.Case/param  # GetParam() = ..."; the report file is named
        # after the gtest name alone.
        string(REGEX REPLACE "  # GetParam\\(\\) = .*$" "" _n "${_n}")
        string(STRIP "${_n}" _n)
        list(APPEND _names "${_n}")
    endforeach()
    set(${out} "${_names}" PARENT_SCOPE)
endfunction()

_ctest_names(_labelled -L "^hardcase$")
_ctest_names(_all)
list(REMOVE_ITEM _labelled hard_cases_doc)
list(SORT _labelled)

# Families, in table order.
file(STRINGS "${SOURCE_DIR}/tests/hardcase_families.txt" _famlines REGEX "^[a-z]")
set(_families "")
foreach(_l IN LISTS _famlines)
    string(REGEX MATCH "^([a-z0-9-]+) *\\| *(.*)$" _m "${_l}")
    list(APPEND _families "${CMAKE_MATCH_1}")
    set(_title_${CMAKE_MATCH_1} "${CMAKE_MATCH_2}")
    set(_rows_${CMAKE_MATCH_1} "")
    set(_count_${CMAKE_MATCH_1} 0)
    set(_tests_${CMAKE_MATCH_1} "")
endforeach()

# A table cell: | escaped, trimmed.
function(_cell out text)
    string(REPLACE "|" "\\|" _t "${text}")
    string(REPLACE "\n" " " _t "${_t}")
    set(${out} "${_t}" PARENT_SCOPE)
endfunction()

set(_machine_rows 0)
foreach(_test IN LISTS _labelled)
    string(REPLACE "/" "~" _file "${_test}")
    set(_path "${_reports}/${_file}.jsonl")
    if(NOT EXISTS "${_path}")
        string(APPEND _errors "  ${_test}: labelled hardcase but has no report "
                              "(${_path}; run it, or it reports nothing)\n")
        continue()
    endif()
    file(STRINGS "${_path}" _lines)
    if(NOT _lines)
        string(APPEND _errors "  ${_test}: empty report ${_path}\n")
    endif()
    foreach(_json IN LISTS _lines)
        foreach(_k family case quantity bound worst deterministic)
            string(JSON _${_k} ERROR_VARIABLE _jerr GET "${_json}" ${_k})
            if(_jerr)
                string(APPEND _errors "  ${_test}: report line without '${_k}': ${_json}\n")
            endif()
        endforeach()
        # Optional: the rounding-size change of a stability row.
        string(JSON _perturbation ERROR_VARIABLE _jerr GET "${_json}" perturbation)
        if(_jerr OR _perturbation STREQUAL "")
            set(_perturbation "-")
        endif()
        if(NOT DEFINED _title_${_family})
            string(APPEND _errors "  ${_test}: unknown family '${_family}' "
                                  "(tests/hardcase_families.txt)\n")
            continue()
        endif()
        _cell(_c "${_case}")
        _cell(_p "${_perturbation}")
        _cell(_q "${_quantity}")
        _cell(_b "${_bound}")
        _cell(_w "${_worst}")
        if(NOT _deterministic)
            set(_w "${_w} †")
            math(EXPR _machine_rows "${_machine_rows} + 1")
        endif()
        string(APPEND _rows_${_family} "| ${_c} | ${_p} | ${_q} | ${_b} | ${_w} | `${_test}` |\n")
        math(EXPR _count_${_family} "${_count_${_family}} + 1")
        list(APPEND _tests_${_family} "${_test}")
    endforeach()
endforeach()

# Reports of tests that exist but are not labelled (stale files of renamed
# or removed tests are ignored).
file(GLOB _files RELATIVE "${_reports}" "${_reports}/*.jsonl")
foreach(_f IN LISTS _files)
    string(REGEX REPLACE "\\.jsonl$" "" _t "${_f}")
    string(REPLACE "~" "/" _t "${_t}")
    list(FIND _labelled "${_t}" _i)
    list(FIND _all "${_t}" _j)
    if(_i EQUAL -1 AND NOT _j EQUAL -1)
        string(APPEND _errors "  ${_t}: reports hard cases but is not labelled hardcase "
                              "(HARDCASE pattern of its surfgrad_add_test)\n")
    endif()
endforeach()

if(_errors)
    message(FATAL_ERROR "hard cases: the tests' reports are not complete:\n${_errors}")
endif()

# The document.
set(_md "# Hard cases: numerical stability, tested\n\n")
string(APPEND _md "<!-- Generated by scripts/hard-cases from the reports of the tests labelled "
                  "`hardcase` (tests/common/hardcase.h); do not edit. The ctest hard_cases_doc "
                  "fails when this file and the tests disagree. -->\n\n")
string(APPEND _md
    "Users asked: *\"Hard cases stay numerically stable: not only finite and bounded; a "
    "rounding-size change of the input moves the output by a rounding-size amount, and the "
    "GPU agrees with the CPU reference; tested on generated cases, not only the ones we "
    "thought of.\"* Every row below is a check a test makes, with the bound it asserts and "
    "the worst value it measured on its inputs; the tests are the `hardcase` label of "
    "ctest:\n\n"
    "    ctest -L hardcase            # in a build directory: every numerical-stability test\n"
    "    scripts/hard-cases [BUILD]   # runs them and rewrites this file (default ./build)\n\n"
    "A test reports its rows with `sg::test::reportHardCase` or `hardCaseAtMost` "
    "(tests/common/hardcase.h) under one of the families of "
    "`tests/hardcase_families.txt`, and is labelled by the `HARDCASE` pattern of its "
    "`surfgrad_add_test` (tests/CMakeLists.txt). The ctest `hard_cases_doc` runs after "
    "them and fails if this file differs from what they reported (case, quantity, bound, "
    "test and measured value), or if a labelled test reports nothing. Measured values "
    "are deterministic for a given build except those marked †: they come from llvmpipe, "
    "whose arithmetic depends on the CPU's vector width and the LLVM version, and the check "
    "ignores them. Bounds are the tests' own; each test's source says why the bound is what "
    "it is.\n\n"
    "**Stability, not only finiteness.** A row with a *perturbation* renders (or "
    "evaluates) its input twice, as given and after the rounding-size change named there "
    "(a UV, position or normal coordinate moved by a couple of binary32 ulps, the camera by "
    "2^-21 of its distance, ...), and bounds how far the output moves; rows of "
    "`Stability.*` (tests/render/stability_test.cpp, cases in "
    "bench/accuracy/stability_cases.cpp) do so for every hard-case family crossed with every "
    "layer kind, for the named inputs users meet, and for random meshes, charts, "
    "transforms and cameras, and compare the GPU with the CPU reference that uses the "
    "GPU's derivative and LOD rules. The same measurements before and after the fixes "
    "that made them stable, as condition numbers, are table 12 of "
    "`docs/accuracy-cost.md`.\n\n")
list(LENGTH _labelled _ntests)
string(APPEND _md "## Families\n\n| family | rows | tests |\n|---|---:|---:|\n")
foreach(_f IN LISTS _families)
    set(_t "${_tests_${_f}}")
    if(_t)
        list(REMOVE_DUPLICATES _t)
    endif()
    list(LENGTH _t _nt)
    string(TOLOWER "${_title_${_f}}" _anchor)
    string(REGEX REPLACE "[^a-z0-9 -]" "" _anchor "${_anchor}")
    string(REPLACE " " "-" _anchor "${_anchor}")
    if(_count_${_f} EQUAL 0)
        string(APPEND _md "| [${_title_${_f}}](#${_anchor}) | **no test yet** | 0 |\n")
    else()
        string(APPEND _md "| [${_title_${_f}}](#${_anchor}) | ${_count_${_f}} | ${_nt} |\n")
    endif()
endforeach()
string(APPEND _md "\n${_ntests} tests carry the label.\n")
foreach(_f IN LISTS _families)
    string(APPEND _md "\n## ${_title_${_f}}\n\n")
    string(APPEND _md "| case | perturbation | quantity checked | bound | worst measured | test |\n")
    string(APPEND _md "|---|---|---|---|---|---|\n")
    if(_count_${_f} EQUAL 0)
        string(APPEND _md "| **no test yet**: this row is filled when a test reports family "
                          "`${_f}` | | | | | |\n")
    else()
        string(APPEND _md "${_rows_${_f}}")
    endif()
endforeach()

if(MODE STREQUAL "generate")
    file(WRITE "${_doc}" "${_md}")
    message(STATUS "hard cases: wrote ${_doc} (${_ntests} tests, ${_machine_rows} "
                   "machine-dependent values)")
elseif(MODE STREQUAL "check")
    if(NOT EXISTS "${_doc}")
        message(FATAL_ERROR "hard cases: ${_doc} does not exist (run scripts/hard-cases)")
    endif()
    file(READ "${_doc}" _have)
    # Machine-dependent values are not compared.
    set(_norm_re "\\| [^|\n]* † \\|")
    string(REGEX REPLACE "${_norm_re}" "| † |" _have_n "${_have}")
    string(REGEX REPLACE "${_norm_re}" "| † |" _want_n "${_md}")
    # Another build configuration (a sanitizer build, RelWithDebInfo) rounds
    # differently in the last printed digit (1.57e-07 against 1.51e-07): the
    # page's figures are compared exactly only in the configuration that
    # wrote it (Release, scripts/test); elsewhere every number is masked and
    # the rows, cases and verdicts are still compared.
    if(NOT EXACT_FIGURES)
        set(_num_re "[-+]?[0-9]+([.][0-9]+)?([eE][-+]?[0-9]+)?")
        string(REGEX REPLACE "${_num_re}" "#" _have_n "${_have_n}")
        string(REGEX REPLACE "${_num_re}" "#" _want_n "${_want_n}")
    endif()
    if(NOT _have_n STREQUAL _want_n)
        # Name the first line that differs.
        string(REPLACE "\n" ";" _hl "${_have_n}")
        string(REPLACE "\n" ";" _wl "${_want_n}")
        list(LENGTH _hl _nh)
        list(LENGTH _wl _nw)
        set(_i 0)
        set(_msg "")
        while(_i LESS _nh OR _i LESS _nw)
            set(_a "")
            set(_b "")
            if(_i LESS _nh)
                list(GET _hl ${_i} _a)
            endif()
            if(_i LESS _nw)
                list(GET _wl ${_i} _b)
            endif()
            if(NOT _a STREQUAL _b)
                math(EXPR _line "${_i} + 1")
                set(_msg "line ${_line}:\n  docs/hard-cases.md: ${_a}\n  the tests report: ${_b}")
                break()
            endif()
            math(EXPR _i "${_i} + 1")
        endwhile()
        message(FATAL_ERROR "hard cases: docs/hard-cases.md is out of step with the tests "
                            "(run scripts/hard-cases); first difference at ${_msg}")
    endif()
    message(STATUS "hard cases: docs/hard-cases.md agrees with ${_ntests} tests")
else()
    message(FATAL_ERROR "HardCases.cmake: MODE must be generate or check")
endif()
