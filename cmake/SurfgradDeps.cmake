# All third-party packages, found once. Installed on Debian 12 by
# scripts/setup-deps (see README). Quirks handled here are documented in
# docs/platform.md.
#
# What the libraries link is found by cmake/surfgradDependencies.cmake,
# which the installed surfgradConfig.cmake runs too (the same code, one
# place: OpenSubdiv through cmake/FindOpenSubdiv.cmake, OpenImageIO's
# opencv4 include directory filtered out).
set(_surfgrad_with_viewer ${SURFGRAD_BUILD_VIEWER})
include(surfgradDependencies)

# The CLI, the tests and the benchmarks only.
find_package(CLI11 REQUIRED)
if(SURFGRAD_BUILD_TESTS)
    find_package(GTest REQUIRED)
    find_package(rapidcheck REQUIRED) # property tests (tests/bump/property_test.cpp)
endif()
if(SURFGRAD_BUILD_BENCH)
    find_package(benchmark REQUIRED)
endif()
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
