// Contract checks: how every surfgrad module states the preconditions,
// postconditions and internal invariants whose violation is a CALLER BUG
// (docs/architecture.md, "Errors"). Untrusted input (files, scene fields,
// command-line values) is never checked with these: it is validated where
// it is read and rejected with sg::io::InputError (surfgrad/base/io.h).
//
//   SG_EXPECTS(cond, msg)  precondition of a function, at its top
//   SG_ENSURES(cond, msg)  postcondition, before it returns
//   SG_ASSERT(cond, msg)   internal invariant of an implementation
//
// `msg` is a string literal saying what the caller got wrong.
//
// Checked builds (CMake option SURFGRAD_CONTRACTS=ON, which defines
// SURFGRAD_CONTRACTS=1 on every first-party target; the default for Debug
// and sanitizer builds, and what scripts/test builds): a failed check prints
//   <file>:<line>: contract violated: <cond> (<msg>)
// to stderr and calls std::abort() (the death tests rely on this).
// Release builds (SURFGRAD_CONTRACTS off): every check compiles to nothing
// and `cond` is NOT evaluated (it must have no side effects); a violated
// contract is then undefined behaviour, so callers must not rely on a check
// to catch their mistakes.
#pragma once

namespace sg::contract {

// Prints "<file>:<line>: contract violated: <cond> (<msg>)" to stderr and
// aborts. Called only by the macros below.
[[noreturn]] void violated(const char* cond, const char* msg, const char* file, int line) noexcept;

} // namespace sg::contract

#if defined(SURFGRAD_CONTRACTS) && SURFGRAD_CONTRACTS
#define SG_CONTRACT_CHECK_(cond, msg)                                                              \
    (static_cast<bool>(cond) ? static_cast<void>(0)                                                \
                             : ::sg::contract::violated(#cond, msg, __FILE__, __LINE__))
#else
// Unevaluated operand: the condition still has to compile (and names in it
// count as used), but no code is generated and nothing is evaluated.
#define SG_CONTRACT_CHECK_(cond, msg) static_cast<void>(sizeof(static_cast<bool>(cond)))
#endif

#define SG_EXPECTS(cond, msg) SG_CONTRACT_CHECK_(cond, msg)
#define SG_ENSURES(cond, msg) SG_CONTRACT_CHECK_(cond, msg)
#define SG_ASSERT(cond, msg) SG_CONTRACT_CHECK_(cond, msg)
