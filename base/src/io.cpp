// Input/output policy helpers (see surfgrad/io.h).
#include "surfgrad/io.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include <unistd.h>

namespace sg::io {

namespace fs = std::filesystem;

InputError::InputError(std::string file, std::string element, std::string reason)
    : std::runtime_error(file + ": " + (element.empty() ? "" : element + ": ") + reason),
      file_(std::move(file)), element_(std::move(element)), reason_(std::move(reason)) {}

void writeAtomically(const fs::path& path, const std::function<void(const fs::path&)>& write) {
    std::error_code ec;
    if (path.empty()) throw InputError("(output)", "", "empty output path");
    if (fs::is_directory(path, ec)) throw InputError(path.string(), "", "is a directory");
    fs::path dir = path.parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec)) {
        throw InputError(path.string(), "", "output directory " + dir.string() + " does not exist");
    }
    static std::atomic<unsigned> counter{0};
    // Keep the extension last: writers such as OpenImageIO pick the format
    // from it.
    fs::path tmp = dir / ("." + path.stem().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                          std::to_string(counter++) + path.extension().string());
    try {
        write(tmp);
    } catch (...) {
        fs::remove(tmp, ec);
        throw;
    }
    if (!fs::exists(tmp, ec)) {
        throw InputError(path.string(), "", "writer produced no file");
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw InputError(path.string(), "", "cannot rename temporary file: " + ec.message());
    }
}

void writeFileAtomically(const fs::path& path, const std::string& bytes) {
    writeAtomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        if (!out)
            throw InputError(path.string(), "",
                             std::string("cannot open for writing: ") + std::strerror(errno));
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) throw InputError(path.string(), "", "write failed (disk full?)");
    });
}

void checkNotInput(const fs::path& output, std::initializer_list<fs::path> inputs) {
    std::error_code ec;
    for (const auto& in : inputs) {
        if (in.empty()) continue;
        if (fs::exists(output, ec) && fs::exists(in, ec) && fs::equivalent(output, in, ec)) {
            throw InputError(output.string(), "",
                             "output would overwrite the input " + in.string());
        }
    }
}

std::string readFile(const fs::path& path, std::size_t maxBytes) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path.string(), "", "no such file");
    if (!fs::is_regular_file(path, ec)) throw InputError(path.string(), "", "not a regular file");
    auto size = fs::file_size(path, ec);
    if (ec) throw InputError(path.string(), "", "cannot read size: " + ec.message());
    if (size > maxBytes) {
        throw InputError(path.string(), "",
                         "file is " + std::to_string(size) + " bytes; limit is " +
                             std::to_string(maxBytes));
    }
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError(path.string(), "", std::string("cannot open: ") + std::strerror(errno));
    std::string data(size, '\0');
    in.read(data.data(), std::streamsize(size));
    if (std::size_t(in.gcount()) != size) throw InputError(path.string(), "", "short read");
    return data;
}

} // namespace sg::io
