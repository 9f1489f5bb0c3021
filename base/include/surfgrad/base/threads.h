// Threads: the one convention by which every surfgrad job that runs on
// several cores (tangents, refinement, stencils, limit evaluation, feature
// bakes, the normal-map operations, the CPU renderer) is told how many, in
// the API and in the CLI's --threads:
//
//   0        TBB's default concurrency: all cores, still capped by any
//            tbb::global_control the caller holds (the CLI's --threads sets
//            one for the whole command)
//   1        the calling thread only
//   2..1024  a tbb::task_arena of that many threads
//
// The output of every job is the same bits for every thread count: parallel
// steps write disjoint outputs or reduce in a fixed order (never in the order
// tasks finish). Jobs keep inputs below a measured size on the calling thread
// whatever the count, where threads cost more than they save; each job states
// its cut-over at its declaration.
//
// A caller bug (a count outside 0..1024 given to the API) is a contract
// violation (surfgrad/base/contract.h); untrusted counts (command lines, scene
// files) are checked with threadCountProblem() where they are read.
#pragma once

#include <string>
#include <type_traits>
#include <utility>

#include <tbb/task_arena.h>

namespace sg {

inline constexpr int kMaxThreads = 1024;

// Empty when 0 <= threads <= kMaxThreads; otherwise a sentence saying why
// not ("thread count 2000 is above 1024").
inline std::string threadCountProblem(int threads) {
    if (threads < 0) return "thread count " + std::to_string(threads) + " is negative";
    if (threads > kMaxThreads) {
        return "thread count " + std::to_string(threads) + " is above " +
               std::to_string(kMaxThreads);
    }
    return {};
}

// Runs f() in a tbb::task_arena of `threads` threads (0: automatic) and
// returns its result; TBB loops inside f run on that arena's threads only.
// `threads` must be 0..kMaxThreads (unchecked here: check it at the API).
template <class F>
decltype(auto) runWithThreads(int threads, F&& f) {
    tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic : threads);
    return arena.execute(std::forward<F>(f));
}

} // namespace sg
