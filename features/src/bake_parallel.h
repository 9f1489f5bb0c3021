// Parallel loops of the feature-map bake and packing (features/src): fixed
// blocks of a loop's range run on the threads of the caller's TBB arena
// (surfgrad/base/threads.h), or in order on the calling thread when the job is
// below its serial cut-over or given one thread. Bodies write disjoint
// outputs; per-block results (counters) are combined in block order, so
// every output is the same for every thread count and every scheduling.
// Progress is reported from the calling thread only (callbacks need not be
// thread-safe).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sg::features::detail {

// How a job runs its loops: in parallel on the current arena, or serially.
struct Exec {
    bool parallel = false;
};

inline size_t blockCount(size_t count, size_t grain) {
    return (count + grain - 1) / grain;
}

// body(block, begin, end) for the blocks [b * grain, min((b + 1) * grain,
// count)) of [0, count): in parallel (any order, one task per block) or in
// block order on the calling thread. The blocks are the same either way.
template <class F>
void forBlocks(const Exec& ex, size_t count, size_t grain, F&& body) {
    const size_t blocks = blockCount(count, grain);
    auto run = [&](size_t b) { body(b, b * grain, std::min(count, (b + 1) * grain)); };
    if (!ex.parallel || blocks <= 1) {
        for (size_t b = 0; b < blocks; ++b) run(b);
        return;
    }
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, blocks, 1),
        [&](const tbb::blocked_range<size_t>& r) {
            for (size_t b = r.begin(); b != r.end(); ++b) run(b);
        },
        tbb::simple_partitioner());
}

// Progress of one phase over `total` units of work, reported at most every
// 200 ms and only by the thread that created it (the bake's caller); add()
// may be called from any thread.
class PhaseProgress {
public:
    PhaseProgress(const std::function<void(const char*, double)>& report, const char* phase,
                  size_t total)
        : report_(report), phase_(phase), total_(std::max<size_t>(total, 1)) {}
    void add(size_t units) {
        const size_t done = done_.fetch_add(units, std::memory_order_relaxed) + units;
        if (!report_ || std::this_thread::get_id() != owner_) return;
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(200)) return;
        last_ = now;
        report_(phase_, double(std::min(done, total_)) / double(total_));
    }
    // The phase's end, whatever the throttle skipped (calling thread).
    void finish() {
        if (report_) report_(phase_, 1.0);
    }

private:
    const std::function<void(const char*, double)>& report_;
    const char* phase_;
    size_t total_;
    std::atomic<size_t> done_{0};
    std::thread::id owner_ = std::this_thread::get_id();
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

} // namespace sg::features::detail
