// Embedded GLSL lookup and #include expansion (see shader_files.h).
#include "surfgrad/shader_files.h"

#include <algorithm>
#include <regex>
#include <set>
#include <sstream>

namespace sg::shaders {

const char* find(std::string_view path) {
    for (int i = 0; i < kEmbeddedFileCount; ++i) {
        if (path == kEmbeddedFiles[i].path) return kEmbeddedFiles[i].text;
    }
    return nullptr;
}

std::vector<std::string> list() {
    std::vector<std::string> out;
    for (int i = 0; i < kEmbeddedFileCount; ++i) out.emplace_back(kEmbeddedFiles[i].path);
    std::sort(out.begin(), out.end());
    return out;
}

namespace {

struct Expander {
    Assembled& out;
    std::set<std::string> included;

    int fileIndex(const std::string& name) {
        auto it = std::find(out.files.begin(), out.files.end(), name);
        if (it != out.files.end()) return int(it - out.files.begin());
        out.files.push_back(name);
        return int(out.files.size()) - 1;
    }

    void expand(std::string_view text, const std::string& name, int depth) {
        if (depth > 32) {
            throw ShaderSourceError(name + ": #include nesting deeper than 32 (a cycle?)");
        }
        const int self = fileIndex(name);
        out.text += "#line 1 " + std::to_string(self) + "\n";
        std::istringstream in{std::string(text)};
        std::string line;
        int lineNo = 0;
        while (std::getline(in, line)) {
            ++lineNo;
            size_t p = line.find_first_not_of(" \t");
            if (p != std::string::npos && line.compare(p, 8, "#include") == 0) {
                size_t q0 = line.find('"', p + 8);
                size_t q1 = q0 == std::string::npos ? q0 : line.find('"', q0 + 1);
                if (q1 == std::string::npos) {
                    throw ShaderSourceError(name + ":" + std::to_string(lineNo) +
                                            ": malformed #include (expected \"path\")");
                }
                std::string path = line.substr(q0 + 1, q1 - q0 - 1);
                if (!included.count(path)) {
                    const char* src = find(path);
                    if (!src) {
                        throw ShaderSourceError(name + ":" + std::to_string(lineNo) +
                                                ": #include \"" + path +
                                                "\": no such embedded shader file");
                    }
                    included.insert(path);
                    expand(src, path, depth + 1);
                    out.text +=
                        "#line " + std::to_string(lineNo + 1) + " " + std::to_string(self) + "\n";
                } else {
                    out.text += "\n";
                }
                continue;
            }
            out.text += line;
            out.text += '\n';
        }
    }
};

} // namespace

Assembled assemble(std::string_view body, std::string_view bodyName,
                   const std::vector<std::string>& defines) {
    Assembled a;
    a.text = "#version 450 core\n";
    for (const auto& d : defines) {
        std::string def = d;
        std::replace(def.begin(), def.end(), '=', ' ');
        a.text += "#define " + def + "\n";
    }
    Expander e{a, {}};
    e.expand(body, std::string(bodyName), 0);
    return a;
}

std::string annotateLog(std::string_view log, const std::vector<std::string>& files) {
    // Mesa writes "0:12(5): error: ...", glslang "ERROR: 0:12: ...".
    static const std::regex loc(R"((\d+):(\d+)(\(\d+\))?)");
    std::string s(log);
    std::string result;
    std::sregex_iterator it(s.begin(), s.end(), loc), end;
    size_t last = 0;
    for (; it != end; ++it) {
        const auto& m = *it;
        size_t idx = std::stoul(m[1].str());
        result.append(s, last, size_t(m.position()) - last);
        if (idx < files.size()) {
            result += files[idx] + ":" + m[2].str() + m[3].str();
        } else {
            result += m.str();
        }
        last = size_t(m.position() + m.length());
    }
    result.append(s, last, std::string::npos);
    return result;
}

} // namespace sg::shaders
