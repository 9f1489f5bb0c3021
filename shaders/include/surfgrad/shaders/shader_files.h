// The embedded GLSL library and the program assembler.
//
// Every file under shaders/ is compiled into the binary (see
// cmake/EmbedShaders.cmake) and addressed by its path relative to shaders/,
// e.g. "sg/surfgrad.glsl". GLSL has no #include, so assemble() expands
// `#include "path"` lines itself, each file at most once per program, and
// inserts `#line L S` directives so driver messages name the real file:
// source-string number S is the file's index in the returned `files` list.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sg::shaders {

struct EmbeddedFile {
    const char* path;
    const char* text;
};
extern const EmbeddedFile kEmbeddedFiles[];
extern const int kEmbeddedFileCount;

// Text of an embedded file, or nullptr when there is none with that path.
const char* find(std::string_view path);

// Paths of all embedded files, sorted.
std::vector<std::string> list();

// A missing include or a malformed #include line: names the including file
// and line.
struct ShaderSourceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The GLSL dialect a program is assembled for (docs/engines.md). The
// library source is one; compat.glsl adapts it to the dialect by
// __VERSION__ and GL_ES, and assemble() writes the header:
//   Glsl450  "#version 450 core" (desktop GL 4.5; glslang -V makes Vulkan
//            SPIR-V from the same text);
//   Glsl330  "#version 330 core" (GL 3.3: no compute or tessellation
//            stages; backslash line continuations are joined, since GLSL
//            before 4.20 has none);
//   Es300    "#version 300 es" with highp defaults for float, int,
//            sampler2D and usampler2D (WebGL2, GLES 3.0: no
//            compute or tessellation stages).
//   Hlsl     no header: the body is an HLSL file that includes
//            sg/surfgrad.hlsl (or sg/compat.hlsl before other library
//            files), whose macros spell the source as HLSL.
//            No GL driver compiles it: the test suite translates it
//            (glslang's HLSL front end to SPIR-V, SPIRV-Cross to GLSL 4.50)
//            and runs the translation on an OpenGL 4.5 context. Its #line
//            directives name files as strings (`#line L "file"`).
enum class Target { Glsl450, Glsl330, Es300, Hlsl };
// The GLSL dialects, which a GL context of this machine compiles and runs.
inline constexpr Target kTargets[] = {Target::Glsl450, Target::Glsl330, Target::Es300};
// "glsl450", "glsl330", "es300", "hlsl".
const char* targetName(Target t);
// The GLSL target (kTargets) named `name` (as targetName writes it); false
// when none is.
bool parseTarget(std::string_view name, Target& out);

struct Assembled {
    std::string text;               // complete GLSL source, #version first
    std::vector<std::string> files; // source-string number -> file name
};

// Builds a complete program of dialect `target` (GLSL 4.50 by default)
// from `body` (named `bodyName` in messages): the #version line (with ES's
// default precisions), then one `#define NAME VALUE` per entry of `defines`
// ("NAME" or "NAME VALUE"), then the body with includes expanded.
Assembled assemble(std::string_view body, std::string_view bodyName,
                   const std::vector<std::string>& defines = {}, Target target = Target::Glsl450);

// A complete GLSL 4.50 program (first line `#version 450 ...`, e.g. what
// assemble() or the renderer wrote) in another GLSL dialect: its first line
// replaced by the dialect's header as assemble() writes it (ES 3.00's highp
// defaults, sampler2D included, since ES's default lowp sampler rounds
// texels; GLSL 3.30's joined continuation lines), a `#line 2 0` keeping the
// compilers' line numbers those of the 4.50 text. The program must be
// valid in the dialect (sg/compat.glsl adapts the library; no stage or
// buffer the dialect lacks). Throws ShaderSourceError unless target is a
// GLSL dialect (kTargets) and the text starts with "#version 450".
std::string inDialect(const std::string& glsl450Program, Target target);

// The library files `entryPaths` (e.g. {"sg/surfgrad.hlsl"}) as ONE file:
// each with its includes expanded in place, every file once, a
// `// ---- path` comment where each begins (no #line, no #version),
// continuation lines joined, `banner` (lines, each written as a comment)
// first. For engines with no #include of their own or with rules about
// include names (WebGL and three.js take shader strings; Unreal includes
// only .ush files): the build writes share/surfgrad/shaders/flat/ from it
// (docs/engines.md). Throws ShaderSourceError for an unknown file.
std::string flatten(const std::vector<std::string>& entryPaths, std::string_view banner);

// The single-file library the build installs in share/surfgrad/shaders/flat
// (surfgrad_flatten): surfgrad.glsl (every GLSL dialect; the program writes
// its #version and, for ES, its precisions), surfgrad.hlsl and surfgrad.ush
// (the same HLSL text; Unreal includes only .ush/.usf files). Each holds the
// core library (sg/surfgrad.glsl), the volume noise (sg/render/noise.glsl)
// and the common normal-map blends (sg/normal_blends.glsl).
struct FlatFile {
    std::string name; // file name, e.g. "surfgrad.hlsl"
    std::string text;
};
std::vector<FlatFile> flatLibrary();

// Maps "S:L" / "S(L)" locations in a driver info log to "file:L".
std::string annotateLog(std::string_view log, const std::vector<std::string>& files);

} // namespace sg::shaders
