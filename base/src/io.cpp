// Input/output policy helpers (see surfgrad/base/io.h).
#include "surfgrad/base/io.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include <unistd.h>

namespace sg::io {

namespace fs = std::filesystem;

std::string printable(std::string_view text, std::size_t maxBytes) {
    std::string out;
    out.reserve(std::min(text.size(), maxBytes) + 8);
    auto escape = [&](unsigned char b) {
        static const char* kHex = "0123456789abcdef";
        out += "\\x";
        out += kHex[b >> 4];
        out += kHex[b & 15];
    };
    // Length of the well-formed UTF-8 sequence at i that is not a C1
    // control character (U+0080..U+009F), or 0 (RFC 3629, sec. 4).
    auto sequence = [&](std::size_t i) -> std::size_t {
        const auto at = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
        const unsigned char b = at(i);
        std::size_t n = 0;
        unsigned char lo = 0x80, hi = 0xbf; // range of the second byte
        if (b >= 0xc2 && b <= 0xdf) {
            n = 2;
            if (b == 0xc2) lo = 0xa0; // U+0080..U+009F are C1 controls
        } else if (b >= 0xe0 && b <= 0xef) {
            n = 3;
            if (b == 0xe0) lo = 0xa0; // overlong
            if (b == 0xed) hi = 0x9f; // surrogates
        } else if (b >= 0xf0 && b <= 0xf4) {
            n = 4;
            if (b == 0xf0) lo = 0x90; // overlong
            if (b == 0xf4) hi = 0x8f; // above U+10FFFF
        } else {
            return 0;
        }
        if (i + n > text.size() || at(i + 1) < lo || at(i + 1) > hi) return 0;
        for (std::size_t k = 2; k < n; ++k) {
            if (at(i + k) < 0x80 || at(i + k) > 0xbf) return 0;
        }
        // Bidirectional controls (Unicode UAX #9, 2.1-2.6: U+061C, U+200E,
        // U+200F, U+202A..U+202E, U+2066..U+2069) reorder what follows them
        // on a terminal, so a path could show as another: escaped too.
        if (n == 2 && b == 0xd8 && at(i + 1) == 0x9c) return 0;
        if (n == 3 && b == 0xe2 && at(i + 1) == 0x80 &&
            (at(i + 2) == 0x8e || at(i + 2) == 0x8f || (at(i + 2) >= 0xaa && at(i + 2) <= 0xae)))
            return 0;
        if (n == 3 && b == 0xe2 && at(i + 1) == 0x81 && at(i + 2) >= 0xa6 && at(i + 2) <= 0xa9)
            return 0;
        return n;
    };
    std::size_t i = 0;
    while (i < text.size()) {
        const unsigned char b = static_cast<unsigned char>(text[i]);
        const std::size_t n = b >= 0x80 ? sequence(i) : 1;
        if (i + std::max<std::size_t>(n, 1) > maxBytes) {
            out += "...";
            break;
        }
        if (b >= 0x20 && b < 0x7f) {
            out += char(b);
        } else if (n > 1) {
            out.append(text.substr(i, n));
        } else {
            escape(b);
        }
        i += std::max<std::size_t>(n, 1);
    }
    return out;
}

InputError::InputError(std::string file, std::string element, std::string reason)
    : std::runtime_error(printable(file + ": " + (element.empty() ? "" : element + ": ") + reason,
                                   std::string::npos)),
      file_(std::move(file)), element_(std::move(element)), reason_(std::move(reason)) {}

namespace {

// `text` with every occurrence of `from` replaced by `to`.
std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
    if (from.empty()) return text;
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size())) {
        text.replace(at, from.size(), to);
    }
    return text;
}

} // namespace

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
    // Error messages name the destination, never the temporary file: the
    // full temporary path first, then its bare file name.
    auto destination = [&](std::string text) {
        text = replaceAll(std::move(text), tmp.string(), path.string());
        return replaceAll(std::move(text), tmp.filename().string(), path.filename().string());
    };
    try {
        write(tmp);
    } catch (const InputError& e) {
        fs::remove(tmp, ec);
        throw InputError(destination(e.file()), destination(e.element()), destination(e.reason()));
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);
        throw InputError(path.string(), "", destination(e.what()));
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

std::string captureStderr(const std::function<void()>& run) {
    std::fflush(stderr);
    FILE* sink = std::tmpfile();
    const int saved = sink ? ::dup(2) : -1;
    if (saved < 0 || ::dup2(::fileno(sink), 2) < 0) {
        // Nothing to capture into: run as is.
        if (saved >= 0) ::close(saved);
        if (sink) std::fclose(sink);
        run();
        return {};
    }
    auto restore = [&] {
        std::fflush(stderr);
        ::dup2(saved, 2);
        ::close(saved);
    };
    try {
        run();
    } catch (...) {
        restore();
        std::fclose(sink);
        throw;
    }
    restore();
    std::string text;
    std::rewind(sink);
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, sink)) > 0;) text.append(buf, n);
    std::fclose(sink);
    if (!text.empty() && text.back() != '\n') text += '\n';
    return text;
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

void checkOutputPath(const fs::path& output, std::initializer_list<fs::path> inputs) {
    checkNotInput(output, inputs);
    const std::string name = output.string();
    std::error_code ec;
    if (output.empty()) throw InputError(name, "", "empty output path");
    if (fs::is_directory(output, ec)) throw InputError(name, "", "is a folder, not a file");
    const fs::path dir = output.has_parent_path() ? output.parent_path() : fs::path(".");
    if (!fs::exists(dir, ec))
        throw InputError(name, "",
                         "cannot be written: the folder " + dir.string() + " does not exist");
    if (!fs::is_directory(dir, ec))
        throw InputError(name, "", "cannot be written: " + dir.string() + " is not a folder");
    std::string probe = (dir / ".surfgrad-probe-XXXXXX").string();
    const int fd = ::mkstemp(probe.data());
    if (fd < 0) {
        throw InputError(name, "",
                         "cannot be written: no new file can be made in " + dir.string() + " (" +
                             std::strerror(errno) + ")");
    }
    ::close(fd);
    fs::remove(probe, ec);
}

bool isInsideFolder(const fs::path& folder, const fs::path& path) {
    std::error_code ec;
    fs::path base = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (ec) return false;
    fs::path full = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec) return false;
    auto b = base.begin(), f = full.begin();
    for (; b != base.end(); ++b, ++f) {
        if (b->empty()) continue; // a trailing separator
        if (f == full.end() || *b != *f) return false;
    }
    return true;
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
