# surfgrad_defaults(target): warnings, sanitizers, contract checks and the
# C++ standard for every first-party target. SURFGRAD_WERROR turns warnings
# into errors (CI); SURFGRAD_CONTRACTS turns the contract checks of
# surfgrad/base/contract.h on (the same on every target, so inline functions
# agree across translation units).
function(surfgrad_defaults tgt)
    target_compile_features(${tgt} PUBLIC cxx_std_20)
    if(SURFGRAD_CONTRACTS)
        target_compile_definitions(${tgt} PRIVATE SURFGRAD_CONTRACTS=1)
    endif()
    if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
        target_compile_options(${tgt} PRIVATE -Wall -Wextra -Wpedantic
                               -Wno-missing-field-initializers)
        if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
            # -Wshadow=local is GCC-only (clang's -Wshadow also flags members).
            target_compile_options(${tgt} PRIVATE -Wshadow=local)
            # GCC 12 reports false -Wrestrict positives inside libstdc++'s
            # std::string operator+ at -O2/-O3 (GCC bug 105329).
            target_compile_options(${tgt} PRIVATE -Wno-restrict)
            if(SURFGRAD_SANITIZE)
                # ASan instrumentation makes GCC's flow analysis report
                # maybe-uninitialized inside libstdc++ (std::regex, optional);
                # the warning stays on in the normal build.
                target_compile_options(${tgt} PRIVATE -Wno-maybe-uninitialized)
            endif()
        endif()
        if(SURFGRAD_WERROR)
            target_compile_options(${tgt} PRIVATE -Werror)
        endif()
    endif()
endfunction()

# surfgrad_export(target NAME name [HEADERS dir]): makes a first-party
# library part of the installed package (cmake/SurfgradInstall.cmake):
#  - the alias surfgrad::<name>, the name consumers use after
#    find_package(surfgrad) and first-party code may use in the build tree;
#  - export name <name> (the installed target is surfgrad::<name> too);
#  - HEADERS: the module's public include directory (its surfgrad/<module>/*.h and umbrella surfgrad/<module>.h),
#    used from the source tree in a build and from <prefix>/include in an
#    installation, where SurfgradInstall.cmake copies its files;
#  - in a build with SURFGRAD_CONTRACTS on, the installed target passes
#    SURFGRAD_CONTRACTS=1 on to consumers, so inline functions of the
#    headers check the same contracts as the library (surfgrad/base/contract.h).
function(surfgrad_export tgt)
    cmake_parse_arguments(E "" "NAME;HEADERS" "" ${ARGN})
    add_library(surfgrad::${E_NAME} ALIAS ${tgt})
    set_target_properties(${tgt} PROPERTIES EXPORT_NAME ${E_NAME})
    if(E_HEADERS)
        target_include_directories(${tgt} PUBLIC "$<BUILD_INTERFACE:${E_HEADERS}>"
                                   "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>")
        set_property(GLOBAL APPEND PROPERTY SURFGRAD_HEADER_DIRS "${E_HEADERS}")
    endif()
    if(SURFGRAD_CONTRACTS)
        target_compile_definitions(${tgt} INTERFACE "$<INSTALL_INTERFACE:SURFGRAD_CONTRACTS=1>")
    endif()
    set_property(GLOBAL APPEND PROPERTY SURFGRAD_EXPORTED_TARGETS ${tgt})
endfunction()
