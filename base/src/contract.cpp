// The failure path of the contract checks (see surfgrad/base/contract.h).
#include "surfgrad/base/contract.h"

#include <cstdio>
#include <cstdlib>

namespace sg::contract {

void violated(const char* cond, const char* msg, const char* file, int line) noexcept {
    std::fflush(stdout);
    std::fprintf(stderr, "%s:%d: contract violated: %s (%s)\n", file, line, cond, msg);
    std::fflush(stderr);
    std::abort();
}

} // namespace sg::contract
