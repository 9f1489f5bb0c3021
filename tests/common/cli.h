// Running programs from tests: the built `surfgrad` CLI (or any command)
// through the shell, with optional stdin text and working directory,
// capturing stdout, stderr and the exit status. Every test that runs a
// program uses these (tests/CMakeLists.txt puts tests/common on the include
// path of every test).
#pragma once

#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

// SG_TEST_ASAN: defined in an AddressSanitizer build (GCC and Clang), where
// tests that limit memory or provoke std::bad_alloc behave differently.
#if defined(__SANITIZE_ADDRESS__)
#define SG_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SG_TEST_ASAN 1
#endif
#endif

namespace sg::test {

struct CommandResult {
    int exitCode = -1; // the program's exit status; -1 if it did not exit normally
    std::string out;   // stdout
    std::string err;   // stderr
    // Both streams (stdout first), for messages that may go to either.
    std::string output() const { return out + err; }
};

struct CommandOptions {
    std::string stdinText;     // written to the program's stdin (empty: /dev/null)
    std::filesystem::path cwd; // working directory (empty: the test's own)
};

// Single-quotes a path or argument for the shell.
inline std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}
inline std::string shellQuote(const std::filesystem::path& p) {
    return shellQuote(p.string());
}

// A scratch folder for this process, <temp>/<prefix>_<pid>, created on the
// first call and removed with everything in it when the process exits (a
// test binary run once per test by ctest would otherwise leave one folder
// per test behind in TMPDIR). One prefix per process.
inline const std::filesystem::path& processScratchDir(const std::string& prefix) {
    struct Owned {
        std::filesystem::path path;
        explicit Owned(std::filesystem::path p) : path(std::move(p)) {
            std::error_code ec;
            std::filesystem::remove_all(path, ec); // a stale folder of a reused pid
            std::filesystem::create_directories(path);
        }
        ~Owned() {
            std::error_code ec;
            std::filesystem::remove_all(path, ec);
        }
    };
    static const Owned owned(std::filesystem::temp_directory_path() /
                             (prefix + "_" + std::to_string(::getpid())));
    return owned.path;
}

// The CLI this build produced.
inline std::filesystem::path surfgradBinary() {
    return std::filesystem::path(SURFGRAD_BINARY_DIR) / "bin" / "surfgrad";
}

// Runs `command` with /bin/sh (so it may hold redirections and pipes).
inline CommandResult runCommand(const std::string& command, const CommandOptions& options = {}) {
    namespace fs = std::filesystem;
    static std::atomic<unsigned> counter{0};
    const fs::path dir =
        fs::temp_directory_path() /
        ("surfgrad_test_cmd_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir);
    const fs::path in = dir / "stdin", err = dir / "stderr";
    std::ofstream(in) << options.stdinText;
    std::string cmd = "{ " + command + " ; } < " + shellQuote(in) + " 2> " + shellQuote(err);
    if (!options.cwd.empty()) cmd = "cd " + shellQuote(options.cwd) + " && " + cmd;
    CommandResult r;
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    if (!pipe) {
        r.err = "popen failed";
    } else {
        std::array<char, 4096> buf;
        while (size_t n = fread(buf.data(), 1, buf.size(), pipe.get())) r.out.append(buf.data(), n);
        const int status = pclose(pipe.release());
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        std::ifstream ef(err);
        r.err.assign(std::istreambuf_iterator<char>(ef), std::istreambuf_iterator<char>());
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
    return r;
}

// Runs the built `surfgrad` with `args` (already shell-quoted where needed).
inline CommandResult runSurfgrad(const std::string& args, const CommandOptions& options = {}) {
    return runCommand(shellQuote(surfgradBinary()) + " " + args, options);
}

// Runs the built `surfgrad` with `args` in `cwd` with at most `limitMiB` of
// memory, so that a test can prove a refusal allocates nothing large: the
// shell's `ulimit -v` in a plain build; in a sanitizer build (ASan reserves
// terabytes of address space, which an address-space limit would refuse)
// ASan's own per-allocation limit, appended to the run's ASAN_OPTIONS
// (scripts/test-sanitize sets some) with allocator_may_return_null so a
// refused allocation surfaces as std::bad_alloc, which the tests look for.
inline CommandResult runSurfgradMemoryLimited(const std::string& args,
                                              const std::filesystem::path& cwd,
                                              unsigned limitMiB = 1500) {
#ifdef SG_TEST_ASAN
    constexpr bool kAsan = true;
#else
    constexpr bool kAsan = false;
#endif
    const std::string limit =
        kAsan ? "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}max_allocation_size_mb=" +
                    std::to_string(limitMiB) + ":allocator_may_return_null=1 exec "
              : "ulimit -v " + std::to_string(limitMiB * 1000) + " && exec ";
    CommandOptions options;
    options.cwd = cwd;
    return runCommand(limit + shellQuote(surfgradBinary()) + " " + args, options);
}

} // namespace sg::test
