// --threads: one option for every command whose work runs on several cores
// (the convention of surfgrad/base/threads.h; contracts in commands.h).
#include <CLI/CLI.hpp>

#include "commands.h"
#include "surfgrad/base/threads.h"

namespace sg::cli {

void addThreadsOption(CLI::App* cmd, int& threads) {
    cmd->add_option("--threads", threads,
                    "worker threads, 1 to " + std::to_string(kMaxThreads) +
                        " (default: all cores); the output is the same for every count")
        ->check(CLI::Range(1, kMaxThreads));
}

std::unique_ptr<tbb::global_control> limitThreads(int threads) {
    if (threads <= 0) return nullptr;
    return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                 size_t(threads));
}

} // namespace sg::cli
