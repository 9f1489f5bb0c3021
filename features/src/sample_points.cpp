// Point files of `surfgrad features sample` (surfgrad/features/feature_maps.h): one
// "x y" pair in texel space per line. Untrusted text: every line is checked
// and a bad one is named (sg::io::InputError).
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"

namespace sg::features {

namespace {

// The whole token is a finite number.
bool parseNumber(std::string_view tok, double& v) {
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size() && std::isfinite(v);
}

} // namespace

std::vector<glm::vec2> parseSamplePoints(std::string_view text, const std::string& name,
                                         std::vector<size_t>* lineNumbers) {
    std::vector<glm::vec2> pts;
    if (lineNumbers) lineNumbers->clear();
    size_t lineNo = 0;
    while (!text.empty()) {
        const size_t eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        std::string_view tok[2];
        int count = 0;
        while (!line.empty()) {
            const size_t b = line.find_first_not_of(" \t");
            if (b == std::string_view::npos) break;
            line.remove_prefix(b);
            const size_t e = std::min(line.find_first_of(" \t"), line.size());
            if (count < 2) tok[count] = line.substr(0, e);
            ++count;
            line.remove_prefix(e);
        }
        if (count == 0) continue;
        double x = 0, y = 0;
        if (count != 2 || !parseNumber(tok[0], x) || !parseNumber(tok[1], y)) {
            throw io::InputError(name, "line " + std::to_string(lineNo),
                                 "expected two finite numbers \"x y\"");
        }
        if (std::fabs(x) > 1e30 || std::fabs(y) > 1e30) {
            throw io::InputError(name, "line " + std::to_string(lineNo),
                                 "coordinate outside float range");
        }
        pts.emplace_back(float(x), float(y));
        if (lineNumbers) lineNumbers->push_back(lineNo);
    }
    return pts;
}

std::vector<glm::vec2> loadSamplePoints(const std::filesystem::path& path,
                                        std::vector<size_t>* lineNumbers) {
    return parseSamplePoints(io::readFile(path, std::size_t(1) << 30), path.string(), lineNumbers);
}

} // namespace sg::features
