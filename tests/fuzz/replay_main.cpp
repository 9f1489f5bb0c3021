// Replay driver for the fuzz entry points in the normal (gcc) test build:
// runs LLVMFuzzerTestOneInput on every file of the given corpus directories
// or files, then on `--mutations N` deterministic random mutations of them
// (byte flips, insertions, deletions, truncations, splices). A crash, an
// ASan/UBSan report (sanitized build) or an uncaught exception fails the
// test; the entry point itself must catch the parser's documented errors.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    size_t mutations = 0;
    std::vector<std::string> inputs;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--mutations" && i + 1 < argc) {
            mutations = std::strtoull(argv[++i], nullptr, 10);
        } else if (fs::is_directory(a)) {
            for (const auto& e : fs::recursive_directory_iterator(a)) {
                if (e.is_regular_file()) inputs.push_back(e.path().string());
            }
        } else {
            inputs.push_back(a);
        }
    }
    std::vector<std::vector<uint8_t>> corpus;
    for (const auto& p : inputs) {
        std::ifstream in(p, std::ios::binary);
        corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    if (corpus.empty()) corpus.emplace_back();
    for (const auto& c : corpus) LLVMFuzzerTestOneInput(c.data(), c.size());

    std::mt19937_64 rng(12345);
    auto rnd = [&](size_t n) { return n ? size_t(rng() % n) : 0; };
    for (size_t m = 0; m < mutations; ++m) {
        std::vector<uint8_t> d = corpus[rnd(corpus.size())];
        int edits = 1 + int(rnd(8));
        for (int e = 0; e < edits; ++e) {
            switch (rnd(5)) {
            case 0:
                if (!d.empty()) d[rnd(d.size())] = uint8_t(rng());
                break;
            case 1:
                d.insert(d.begin() + long(rnd(d.size() + 1)), uint8_t(rng()));
                break;
            case 2:
                if (!d.empty()) d.erase(d.begin() + long(rnd(d.size())));
                break;
            case 3:
                d.resize(rnd(d.size() + 1));
                break;
            default: {
                const auto& o = corpus[rnd(corpus.size())];
                if (!o.empty()) {
                    size_t a = rnd(o.size()), n = rnd(o.size() - a + 1);
                    d.insert(d.begin() + long(rnd(d.size() + 1)), o.begin() + long(a),
                             o.begin() + long(a + n));
                }
            }
            }
        }
        LLVMFuzzerTestOneInput(d.data(), d.size());
    }
    std::printf("replayed %zu corpus inputs and %zu mutations\n", corpus.size(), mutations);
    return 0;
}
