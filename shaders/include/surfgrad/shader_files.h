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

struct Assembled {
    std::string text;               // complete GLSL source, #version first
    std::vector<std::string> files; // source-string number -> file name
};

// Builds a complete GLSL 4.50 program from `body` (named `bodyName` in
// messages): the #version line, then one `#define NAME VALUE` per entry of
// `defines` ("NAME" or "NAME VALUE"), then the body with includes expanded.
Assembled assemble(std::string_view body, std::string_view bodyName,
                   const std::vector<std::string>& defines = {});

// Maps "S:L" / "S(L)" locations in a driver info log to "file:L".
std::string annotateLog(std::string_view log, const std::vector<std::string>& files);

} // namespace sg::shaders
