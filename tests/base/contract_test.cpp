// The contract macros (surfgrad/base/contract.h) in a checked build: a failed
// check prints "<file>:<line>: contract violated: <cond> (<msg>)" and
// aborts; a passing one evaluates its condition once and does nothing else.
#include "contract_death.h"
#include "surfgrad/base/contract.h"

namespace {

using ContractDeath = sg::test::ContractDeath;

int expectsPositive(int x) {
    SG_EXPECTS(x > 0, "x is positive");
    return x;
}

TEST_F(ContractDeath, FailedCheckNamesFileLineConditionAndMessage) {
    EXPECT_DEATH(expectsPositive(-1),
                 "contract_test\\.cpp:[0-9]+: contract violated: x > 0 \\(x is positive\\)");
    EXPECT_DEATH(SG_ENSURES(1 + 1 == 3, "arithmetic"), "contract violated: 1 \\+ 1 == 3");
    EXPECT_DEATH(SG_ASSERT(false, "never"), "contract violated: false \\(never\\)");
}

TEST(Contract, PassingCheckEvaluatesOnceAndContinues) {
    int evaluated = 0;
    SG_EXPECTS(++evaluated == 1, "evaluated once");
    EXPECT_EQ(evaluated, 1);
    EXPECT_EQ(expectsPositive(3), 3);
}

} // namespace
