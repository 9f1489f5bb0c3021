# surfgrad_defaults(target): warnings, sanitizers, contract checks and the
# C++ standard for every first-party target. SURFGRAD_WERROR turns warnings
# into errors (CI); SURFGRAD_CONTRACTS turns the contract checks of
# surfgrad/contract.h on (the same on every target, so inline functions
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
