// Death tests of contract checks (surfgrad/base/contract.h). Registered only when
// the build checks contracts (SURFGRAD_CONTRACTS=ON: Debug, sanitizer and
// scripts/test builds); in Release the checks compile to nothing and these
// calls would be undefined behaviour.
#pragma once

#include <gtest/gtest.h>

#if !(defined(SURFGRAD_CONTRACTS) && SURFGRAD_CONTRACTS)
#error "contract death tests need a build with SURFGRAD_CONTRACTS=ON"
#endif

namespace sg::test {

// Fixture of every contract death test: the "threadsafe" style re-runs the
// test binary for each death test, so GL contexts, thread pools and other
// state of the parent process do not leak into the child.
class ContractDeath : public ::testing::Test {
protected:
    void SetUp() override { GTEST_FLAG_SET(death_test_style, "threadsafe"); }
};

} // namespace sg::test

// `statement` must abort through a contract check whose message contains
// `what` (a regular expression).
#define SG_EXPECT_CONTRACT_DEATH(statement, what)                                                  \
    EXPECT_DEATH(statement, "contract violated: .*" what)
