// Loops of one subdivision job (refinement, stencil application, limit
// evaluation) on TBB, internal to mesh/ (surfgrad/mesh/subdivision.h's
// SubdivisionSettings::threads says what callers see).
//
// Every loop run through Parallel writes disjoint outputs: element i's
// result depends on i alone (and on inputs no other element of the loop
// writes), and each element's floating-point sums run in the serial order
// inside that element. So the output is the same bits whether the range
// runs on the calling thread, in one block or in any split into blocks,
// whatever the thread count. Loops that gather variable-length results
// (SampleTable::add) run in fixed blocks of kFixedBlock elements,
// independent of the thread count, concatenated in block order.
//
// The caller sets `on` (false: every loop runs inline, no TBB at all) and
// runs the job inside sg::runWithThreads (surfgrad/base/threads.h), whose arena
// bounds how many threads the loops use.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <utility>

namespace sg::mesh::detail {

// Elements per task: loops shorter than this run inline even in a parallel
// job (a task costs about a microsecond; one element of these loops 5-50
// ns).
inline constexpr size_t kGrain = 2048;
// Block size of the gathering loops (fixed: the blocks, not the threads,
// decide where a gathered array is cut).
inline constexpr size_t kFixedBlock = 4096;

struct Parallel {
    bool on = false;
    size_t grain = kGrain; // tests set a tiny one to cut small loops into many blocks

    // body(begin, end) over [0, n), in blocks of at least `minGrain`
    // elements (0: `grain`; any split: the body must write disjoint outputs).
    template <class Body>
    void blocks(size_t n, Body&& body, size_t minGrain = 0) const {
        if (n == 0) return;
        const size_t grain = minGrain ? minGrain : this->grain;
        if (!on || n <= grain) {
            body(size_t(0), n);
            return;
        }
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                          [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    }
    // f(i) for every i in [0, n).
    template <class F>
    void each(size_t n, F&& f, size_t minGrain = 0) const {
        blocks(
            n,
            [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) f(i);
            },
            minGrain);
    }
    // f(block, begin, end) for the fixed blocks [k * kFixedBlock, ...) of
    // [0, n); returns the number of blocks.
    template <class F>
    size_t fixedBlocks(size_t n, F&& f) const {
        const size_t count = (n + kFixedBlock - 1) / kFixedBlock;
        each(
            count,
            [&](size_t k) {
                const size_t b = k * kFixedBlock;
                f(k, b, b + kFixedBlock < n ? b + kFixedBlock : n);
            },
            1);
        return count;
    }
};

} // namespace sg::mesh::detail
