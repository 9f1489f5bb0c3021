# surfgrad_defaults(target): warnings, sanitizers and the C++ standard for
# every first-party target. SURFGRAD_WERROR turns warnings into errors (CI).
function(surfgrad_defaults tgt)
    target_compile_features(${tgt} PUBLIC cxx_std_20)
    if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
        target_compile_options(${tgt} PRIVATE -Wall -Wextra -Wpedantic -Wshadow=local
                               -Wno-missing-field-initializers)
        if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
            # GCC 12 reports false -Wrestrict positives inside libstdc++'s
            # std::string operator+ at -O2/-O3 (GCC bug 105329).
            target_compile_options(${tgt} PRIVATE -Wno-restrict)
        endif()
        if(SURFGRAD_WERROR)
            target_compile_options(${tgt} PRIVATE -Werror)
        endif()
    endif()
endfunction()
