// Embedded GLSL lookup and #include expansion (see shader_files.h).
#include "surfgrad/shaders/shader_files.h"

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

const char* targetName(Target t) {
    switch (t) {
    case Target::Glsl450:
        return "glsl450";
    case Target::Glsl330:
        return "glsl330";
    case Target::Es300:
        return "es300";
    case Target::Hlsl:
        return "hlsl";
    }
    return "?";
}

bool parseTarget(std::string_view name, Target& out) {
    for (Target t : kTargets) {
        if (name == targetName(t)) {
            out = t;
            return true;
        }
    }
    return false;
}

namespace {

struct Expander {
    Assembled& out;
    std::set<std::string> included;
    bool joinContinuations = false; // GLSL before 4.20 has no line continuation
    bool namedLines = false;        // HLSL: #line L "file" (GLSL: #line L S)
    bool markers = false;           // flatten(): a comment per file instead of #line

    std::string lineDirective(int line, int self) const {
        const std::string& file = out.files[size_t(self)];
        if (markers) return line == 1 ? "// ---- " + file + "\n" : "// ---- (" + file + ")\n";
        const std::string source = namedLines ? '"' + file + '"' : std::to_string(self);
        return "#line " + std::to_string(line) + " " + source + "\n";
    }

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
        out.text += lineDirective(1, self);
        std::istringstream in{std::string(text)};
        std::string line;
        int lineNo = 0;
        while (std::getline(in, line)) {
            ++lineNo;
            // A backslash at the end joins the next line. The joined lines
            // are kept as empty lines after it, so numbering stays the file's.
            int joined = 0;
            std::string next;
            while (joinContinuations && !line.empty() && line.back() == '\\' &&
                   std::getline(in, next)) {
                line.back() = ' ';
                line += next;
                ++joined;
            }
            if (joined > 0) {
                lineNo += joined;
                out.text += line + '\n' + std::string(size_t(joined), '\n');
                continue;
            }
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
                    out.text += lineDirective(lineNo + 1, self);
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
                   const std::vector<std::string>& defines, Target target) {
    Assembled a;
    switch (target) {
    case Target::Glsl450:
        a.text = "#version 450 core\n";
        break;
    case Target::Glsl330:
        a.text = "#version 330 core\n";
        break;
    case Target::Es300:
        // Precisions for the body's own declarations; sg/compat.glsl states
        // them again for programs that include the library without this.
        a.text = "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                 "precision highp sampler2D;\nprecision highp usampler2D;\n";
        break;
    case Target::Hlsl:
        break;
    }
    for (const auto& d : defines) {
        std::string def = d;
        std::replace(def.begin(), def.end(), '=', ' ');
        a.text += "#define " + def + "\n";
    }
    Expander e{a, {}, target == Target::Glsl330, target == Target::Hlsl};
    e.expand(body, std::string(bodyName), 0);
    return a;
}

std::string inDialect(const std::string& glsl450Program, Target target) {
    if (target == Target::Hlsl || glsl450Program.rfind("#version 450", 0) != 0)
        throw ShaderSourceError("inDialect: a GLSL 4.50 program to a GLSL dialect");
    if (target == Target::Glsl450) return glsl450Program;
    const size_t eol = glsl450Program.find('\n');
    const std::string rest =
        "#line 2 0\n" + (eol == std::string::npos ? std::string() : glsl450Program.substr(eol + 1));
    return assemble(rest, "program", {}, target).text;
}

std::string flatten(const std::vector<std::string>& entryPaths, std::string_view banner) {
    Assembled a;
    for (std::string_view rest = banner; !rest.empty();) {
        const size_t eol = rest.find('\n');
        a.text += "// " + std::string(rest.substr(0, eol)) + "\n";
        rest = eol == std::string_view::npos ? std::string_view() : rest.substr(eol + 1);
    }
    Expander e{a, {}, true, false, true};
    for (const std::string& entry : entryPaths) {
        const char* text = find(entry);
        if (!text) throw ShaderSourceError("flatten: no embedded shader file \"" + entry + "\"");
        if (!e.included.insert(entry).second) continue;
        e.expand(text, entry, 0);
    }
    return a.text;
}

std::vector<FlatFile> flatLibrary() {
    const std::string note = "Generated from shaders/sg by the surfgrad build "
                             "(sg::shaders::flatten). Do not edit: edit shaders/sg.\n";
    const std::string glsl =
        flatten({"sg/surfgrad.glsl", "sg/render/noise.glsl", "sg/normal_blends.glsl"},
                "surfgrad shader library, GLSL (4.50, 3.30, ES 3.00, Vulkan): one file.\n" + note);
    const std::string hlsl =
        flatten({"sg/surfgrad.hlsl", "sg/render/noise.glsl", "sg/normal_blends.glsl"},
                "surfgrad shader library, HLSL (Unity, Unreal, D3D): one file.\n" + note);
    return {{"surfgrad.glsl", glsl}, {"surfgrad.hlsl", hlsl}, {"surfgrad.ush", hlsl}};
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
