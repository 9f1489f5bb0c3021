// The base I/O helpers every reader and writer uses (surfgrad/base/io.h):
// printable() for quoting input in messages, the duplicate-key check of
// JSON input, and error messages of atomic writes that name the
// destination, never the temporary file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <cstring>
#include <unistd.h>

#include "surfgrad/base/io.h"

namespace {

namespace fs = std::filesystem;
using sg::io::InputError;
using sg::io::printable;

TEST(Printable, KeepsTextAndUtf8EscapesControlAndStrayBytes) {
    EXPECT_EQ(printable("vertex 1.5 'x'"), "vertex 1.5 'x'");
    EXPECT_EQ(printable("caf\xc3\xa9 \xe5\xbf\x83"), "caf\xc3\xa9 \xe5\xbf\x83"); // é, 心
    EXPECT_EQ(printable("a\x1b[2Jb"), "a\\x1b[2Jb"); // ESC: a terminal command
    EXPECT_EQ(printable(std::string("\0\r\n\t\x7f", 5)), "\\x00\\x0d\\x0a\\x09\\x7f");
    EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");          // not UTF-8
    EXPECT_EQ(printable("\xc2\x9b"), "\\xc2\\x9b");          // C1 CSI, a terminal command
    EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");          // overlong '/'
    EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80"); // surrogate
    EXPECT_EQ(printable("\xe5\xbf"), "\\xe5\\xbf");          // truncated sequence
    EXPECT_EQ(printable("abcdef", 4), "abcd...");
    EXPECT_EQ(printable("ab\xe5\xbf\x83", 4), "ab..."); // never cut inside a sequence
    EXPECT_EQ(printable(printable("\x01")), "\\x01");   // idempotent
    // Bidirectional controls: a right-to-left override makes "evil\u202Egnp.obj"
    // show as "evilbo.png" (UAX #9); every one of them is escaped.
    EXPECT_EQ(printable("evil\xe2\x80\xaegnp.obj"), "evil\\xe2\\x80\\xaegnp.obj");
    for (const char* control : {"\xd8\x9c", "\xe2\x80\x8e", "\xe2\x80\x8f", "\xe2\x80\xaa",
                                "\xe2\x80\xae", "\xe2\x81\xa6", "\xe2\x81\xa9"}) {
        EXPECT_EQ(printable(control).find('\\'), 0u) << printable(control);
        EXPECT_EQ(printable(control).size(), std::strlen(control) * 4);
    }
    // Their neighbours are printable text: U+2010 (hyphen), U+2070, U+061B.
    EXPECT_EQ(printable("\xe2\x80\x90\xe2\x81\xb0\xd8\x9b"), "\xe2\x80\x90\xe2\x81\xb0\xd8\x9b");
}

// isInsideFolder: "..", absolute paths and symbolic links that lead out are
// outside; a link that stays inside is inside.
TEST(IsInsideFolder, FollowsDotsAndLinks) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("sg_inside_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "model/textures");
    fs::create_directory_symlink(fs::path("/etc"), dir / "model/out");
    fs::create_directory_symlink(fs::path("textures"), dir / "model/in");
    const fs::path model = dir / "model";
    EXPECT_TRUE(sg::io::isInsideFolder(model, model / "a.bin"));
    EXPECT_TRUE(sg::io::isInsideFolder(model, model / "textures/../a.bin"));
    EXPECT_TRUE(sg::io::isInsideFolder(model, model / "in/a.png"));
    EXPECT_FALSE(sg::io::isInsideFolder(model, model / "../a.bin"));
    EXPECT_FALSE(sg::io::isInsideFolder(model, model / "../../../../../../etc/passwd"));
    EXPECT_FALSE(sg::io::isInsideFolder(model, "/etc/passwd"));
    EXPECT_FALSE(sg::io::isInsideFolder(model, model / "out/passwd"));
    EXPECT_FALSE(sg::io::isInsideFolder(model, dir / "model2/a.bin")); // a prefix, not a folder
    fs::remove_all(dir);
}

// checkOutputPath: refused before any work when the output cannot be written.
TEST(CheckOutputPath, RefusesWhatCannotBeWritten) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("sg_outpath_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "file.txt") << "x";
    auto reason = [](const fs::path& p) {
        try {
            sg::io::checkOutputPath(p);
        } catch (const InputError& e) {
            return e.reason();
        }
        return std::string("accepted");
    };
    EXPECT_EQ(reason(dir / "out.png"), "accepted");
    EXPECT_FALSE(fs::exists(dir / "out.png")); // nothing is left behind
    EXPECT_EQ(fs::directory_iterator(dir / "sub") == fs::directory_iterator(), true);
    EXPECT_EQ(reason(dir / "sub"), "is a folder, not a file");
    EXPECT_EQ(reason(dir / "none/out.png"),
              "cannot be written: the folder " + (dir / "none").string() + " does not exist");
    EXPECT_EQ(reason(dir / "file.txt/out.png"),
              "cannot be written: " + (dir / "file.txt").string() + " is not a folder");
    if (::geteuid() != 0) { // root writes into a read-only folder
        fs::permissions(dir / "sub", fs::perms::owner_read | fs::perms::owner_exec);
        EXPECT_NE(reason(dir / "sub/out.png").find("no new file can be made"), std::string::npos);
        fs::permissions(dir / "sub", fs::perms::owner_all);
    }
    fs::remove_all(dir);
}

TEST(InputErrorMessage, QuotedBytesReachTheMessageEscaped) {
    InputError e("in.obj", "line 3", "bad number '\x1b]0;owned\x07'");
    EXPECT_STREQ(e.what(), "in.obj: line 3: bad number '\\x1b]0;owned\\x07'");
    EXPECT_EQ(e.reason(), "bad number '\x1b]0;owned\x07'"); // the parts stay as given
}

std::string duplicateKeyError(const std::string& text) {
    try {
        sg::io::checkJsonKeysUnique(text, "s.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(JsonKeys, DuplicateKeysAreRefusedWithPointerAndKey) {
    EXPECT_EQ(duplicateKeyError(R"({"a": 1, "a": 2})"), "s.json: /: duplicate key \"a\"");
    EXPECT_EQ(duplicateKeyError(R"({"meshes": [{"file": "x"}, {"file": "y", "level": 1,
                                    "subdivision": {"level": 2, "level": 3}}]})"),
              "s.json: /meshes/1/subdivision: duplicate key \"level\"");
    // Array indices count values of every kind; keys with / and ~ are escaped.
    EXPECT_EQ(duplicateKeyError(R"({"a/b~": [1, [2], {"c": 0}, null, {"k": 1, "k": 1}]})"),
              "s.json: /a~1b~0/4: duplicate key \"k\"");
    // Equal keys in different objects, or at different depths, are fine.
    EXPECT_EQ(duplicateKeyError(R"({"a": {"a": 1}, "b": [{"a": 1}, {"a": 2}]})"), "");
    // Malformed text is the caller's parser's to report.
    EXPECT_EQ(duplicateKeyError(R"({"a": 1,)"), "");
    EXPECT_EQ(duplicateKeyError("{\"\x1b\": 1, \"\x1b\": 2}"), "");    // control char: not JSON
    EXPECT_EQ(duplicateKeyError("{\"\xc3\xa9\": 1, \"\xc3\xa9\": 2}"), // é
              "s.json: /: duplicate key \"\xc3\xa9\"");
}

TEST(WriteAtomically, ErrorsNameTheDestinationNotTheTemporaryFile) {
    const fs::path dir = fs::temp_directory_path() / "surfgrad_io_test";
    fs::create_directories(dir);
    const fs::path out = dir / "maps.png";
    std::string tmpSeen;
    try {
        sg::io::writeAtomically(out, [&](const fs::path& tmp) {
            tmpSeen = tmp.string();
            // What a third-party writer says: it names the file it was given.
            throw std::runtime_error("Could not open \"" + tmp.string() + "\" (" +
                                     tmp.filename().string() + ")");
        });
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  out.string() + ": Could not open \"" + out.string() + "\" (maps.png)");
    }
    EXPECT_NE(tmpSeen, out.string());
    EXPECT_FALSE(fs::exists(tmpSeen));
    EXPECT_FALSE(fs::exists(out));
    fs::remove_all(dir);
}

} // namespace
