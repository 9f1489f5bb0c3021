// Input/output policy shared by every module that touches files (features,
// mesh, the renderer and the CLI): one error type for untrusted input and
// atomic output.
//
// Policy (see docs/architecture.md, "Errors"):
//  - contract checks (surfgrad/base/contract.h) for caller bugs;
//  - sg::io::InputError for bad untrusted input: the message names the file,
//    the element (line, key, face index, ...) and the reason;
//  - never a crash, a hang or a silent NaN;
//  - messages that quote input quote it through printable(): bytes a
//    terminal would act on never reach it raw;
//  - outputs are written to a temporary file in the destination directory
//    and renamed over the destination only when complete; an output path
//    that names one of the inputs is refused.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sg::io {

// `text` made safe to show on a terminal, for messages that quote input:
// bytes that are not printable ASCII or part of a well-formed UTF-8
// sequence (control characters, DEL, stray or overlong bytes) and the
// bytes of bidirectional controls (U+202E and the like) become
// "\xNN"; at most maxBytes bytes of `text` are kept, with "..." appended
// when it was cut (never inside a UTF-8 sequence).
std::string printable(std::string_view text, std::size_t maxBytes = 64);

class InputError : public std::runtime_error {
public:
    // what() == "<file>: <element>: <reason>" (element omitted when empty),
    // passed through printable() without a length limit; file(), element()
    // and reason() are the arguments as given.
    InputError(std::string file, std::string element, std::string reason);
    const std::string& file() const { return file_; }
    const std::string& element() const { return element_; }
    const std::string& reason() const { return reason_; }

private:
    std::string file_, element_, reason_;
};

// Writes `path` atomically: `write(tmpPath)` must write the complete file to
// tmpPath (same directory as path, so the rename is atomic); it is renamed
// over path when `write` returns, and removed if `write` throws. The
// exception propagates as an InputError about `path`: a message that names
// the temporary file (third-party writers quote the name they were given)
// names `path` instead. Throws InputError if path is a directory or its
// directory does not exist.
void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path& tmpPath)>& write);

// Same, for a complete in-memory byte string.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

// Throws InputError when `output` refers to the same file as any input
// (inputs are never overwritten).
void checkNotInput(const std::filesystem::path& output,
                   std::initializer_list<std::filesystem::path> inputs);

// For a command about to start long work: throws InputError about `output`
// when it could not be written at the end — its folder is missing or is not
// a folder, the folder refuses a new file (a file is created there and
// removed again), or `output` is a folder — or when it names an input
// (checkNotInput). Writing can still fail later (a full disk).
void checkOutputPath(const std::filesystem::path& output,
                     std::initializer_list<std::filesystem::path> inputs = {});

// True when `path` lies inside `folder` once both are made absolute and
// every symbolic link that exists is resolved (std::filesystem::
// weakly_canonical): a "..", an absolute path or a link that leads out is
// outside. For references found inside input files (a glTF buffer or image
// URI), which must not reach files the user did not hand over.
bool isInsideFolder(const std::filesystem::path& folder, const std::filesystem::path& path);

// Reads a whole file. Throws InputError when it is missing, unreadable, not
// a regular file, or larger than maxBytes.
std::string readFile(const std::filesystem::path& path, std::size_t maxBytes = std::size_t(1)
                                                                               << 30);

// Runs `run` with the process's stderr (file descriptor 2) sent to a
// temporary file, restores it (also when `run` throws; the exception
// propagates) and returns what was written there, each line ended by "\n".
// For third-party decoders that print their own error lines before
// reporting the error to their caller (libpng's "libpng error: ..."
// through OpenImageIO): the caller's message is the one the user sees.
// Process-wide: output of other threads meanwhile is captured too.
std::string captureStderr(const std::function<void()>& run);

// Refuses JSON text in which an object has the same key twice (JSON
// parsers keep one of them silently): throws InputError(file, path, reason)
// with the JSON Pointer (RFC 6901) of the object ("/meshes/0"; "/" for the
// top level) and the key ("duplicate key \"name\""). Text that is not
// well-formed JSON is left to the caller's parser (no error here). Every
// reader of JSON input calls it (scenes, curve networks, eval records,
// glTF).
void checkJsonKeysUnique(std::string_view text, const std::string& file);

} // namespace sg::io
