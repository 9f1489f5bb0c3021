# cmake -DSURFGRAD=<the CLI> -DVERSION=<x.y.z> -DOUT=<dir/surfgrad.1.gz>
#       [-DGZIP=<gzip>] -P ManPage.cmake
# Writes the manual page surfgrad(1) from the CLI's own help: `surfgrad
# --help` as the description, then every command and subcommand's `--help`
# (found from the "Subcommands:" lists of the help texts, depth first) as
# one subsection each. Run at build time (cmake/SurfgradInstall.cmake), so
# the page cannot disagree with the program. Written atomically; compressed
# with gzip -9n (no name or time stamp: reproducible) when GZIP is given.
cmake_minimum_required(VERSION 3.20)
foreach(_v SURFGRAD VERSION OUT)
    if(NOT DEFINED ${_v})
        message(FATAL_ERROR "ManPage.cmake: -D${_v}=... is required")
    endif()
endforeach()

# The help text of `surfgrad <words> --help`; fails naming the command.
function(_sg_help words out)
    execute_process(COMMAND "${SURFGRAD}" ${words} --help
                    OUTPUT_VARIABLE _text ERROR_VARIABLE _err RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0)
        string(REPLACE ";" " " _w "${words}")
        message(FATAL_ERROR "ManPage.cmake: `surfgrad ${_w} --help` exited ${_rc}: ${_err}")
    endif()
    # CLI11 prints the program as invoked: the page names it as installed.
    string(REPLACE "${SURFGRAD}" "surfgrad" _text "${_text}")
    set(${out} "${_text}" PARENT_SCOPE)
endfunction()

# The subcommand names a help text lists (lines "  name  description" after
# a "Subcommands:" heading, up to the next blank line or heading).
function(_sg_subcommands text out)
    string(REPLACE ";" "\\;" text "${text}")
    string(REPLACE "\n" ";" _lines "${text}")
    set(_in FALSE)
    set(_names)
    foreach(_l IN LISTS _lines)
        if(_l MATCHES "^[Ss][Uu][Bb][Cc][Oo][Mm][Mm][Aa][Nn][Dd][Ss]:")
            set(_in TRUE)
        elseif(_in AND _l MATCHES "^  +([A-Za-z0-9][A-Za-z0-9_-]*)( |$)")
            list(APPEND _names "${CMAKE_MATCH_1}")
        elseif(_in AND NOT _l MATCHES "^  ")
            set(_in FALSE)
        endif()
    endforeach()
    set(${out} "${_names}" PARENT_SCOPE)
endfunction()

# Help text as a literal troff block: backslashes escaped, lines that would
# start a request guarded.
function(_sg_troff text out)
    string(REPLACE "\\" "\\e" text "${text}")
    string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
    string(REGEX REPLACE "\n+$" "" text "${text}")
    set(${out} ".nf\n${text}\n.fi\n" PARENT_SCOPE)
endfunction()

_sg_help("" _top)
_sg_troff("${_top}" _desc)
set(_page ".\\\" Generated from the help texts of surfgrad ${VERSION} by cmake/ManPage.cmake.\n")
string(APPEND _page ".TH SURFGRAD 1 \"\" \"surfgrad ${VERSION}\" \"User Commands\"\n"
       ".SH NAME\nsurfgrad \\- surface-gradient bump mapping on subdivision meshes\n"
       ".SH SYNOPSIS\n.B surfgrad\n\\fICOMMAND\\fR [\\fISUBCOMMAND\\fR] [\\fIOPTIONS\\fR]\n"
       ".br\n.B surfgrad\n\\fICOMMAND\\fR \\fB\\-\\-help\\fR\n"
       ".SH DESCRIPTION\n${_desc}.SH COMMANDS\n")

# Depth-first walk of the command tree.
_sg_subcommands("${_top}" _queue)
set(_count 0)
while(_queue)
    list(POP_FRONT _queue _path)
    string(REPLACE " " ";" _words "${_path}")
    _sg_help("${_words}" _text)
    _sg_troff("${_text}" _block)
    string(APPEND _page ".SS \"surfgrad ${_path}\"\n${_block}")
    math(EXPR _count "${_count} + 1")
    _sg_subcommands("${_text}" _subs)
    set(_children)
    foreach(_s IN LISTS _subs)
        list(APPEND _children "${_path} ${_s}")
    endforeach()
    list(PREPEND _queue ${_children})
endwhile()
if(_count EQUAL 0)
    message(FATAL_ERROR "ManPage.cmake: `surfgrad --help` lists no subcommands")
endif()
string(APPEND _page
       ".SH FILES\n.TP\n.I /usr/share/surfgrad/data\n"
       "the data sets that scenes name as \\fBdata:\\fR\\fIFOLDER/FILE\\fR "
       "(\\fBSURFGRAD_DATA_DIR\\fR overrides it)\n"
       ".TP\n.I /usr/share/surfgrad/examples\nthe example scenes\n"
       ".SH COPYRIGHT\nApache License 2.0; the bundled data sets' licenses: "
       ".I /usr/share/doc/surfgrad/copyright\n")

get_filename_component(_dir "${OUT}" DIRECTORY)
file(MAKE_DIRECTORY "${_dir}")
set(_tmp "${OUT}.tmp")
if(DEFINED GZIP AND GZIP)
    file(WRITE "${_tmp}.1" "${_page}")
    execute_process(COMMAND "${GZIP}" -9 -n -c "${_tmp}.1" OUTPUT_FILE "${_tmp}"
                    RESULT_VARIABLE _rc)
    file(REMOVE "${_tmp}.1")
    if(NOT _rc EQUAL 0)
        file(REMOVE "${_tmp}")
        message(FATAL_ERROR "ManPage.cmake: ${GZIP} failed (${_rc})")
    endif()
else()
    file(WRITE "${_tmp}" "${_page}")
endif()
file(RENAME "${_tmp}" "${OUT}")
