// surfgrad command-line entry point: parses the command line (CLI11) and
// runs one subcommand. Every failure ends with one line
//   surfgrad: error: <message>
// on stderr and a non-zero exit status (kExitUsage, kExitFailure in
// commands.h); no partial outputs are left. Messages pass through
// sg::io::printable, so bytes quoted from input never reach the terminal raw.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <exception>
#include <new>
#include <string>

#include "commands.h"
#include "surfgrad/bump/core.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"

#ifndef SURFGRAD_VERSION
#define SURFGRAD_VERSION "0.0.0"
#endif

namespace {

// "mesh subdivide": the deepest subcommand the command line selected.
std::string selectedCommand(const CLI::App& app) {
    std::string path;
    const CLI::App* at = &app;
    for (;;) {
        const std::vector<CLI::App*> subs = at->get_subcommands();
        if (subs.empty()) return path;
        at = subs.back();
        path += (path.empty() ? "" : " ") + at->get_name();
    }
}

// The exit statuses under every --help.
void addFooter(CLI::App& app) {
    app.footer(sg::cli::kExitStatusHelp);
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) addFooter(*sub);
}

void printError(const std::string& message) {
    std::fflush(stdout);
    std::fprintf(stderr, "surfgrad: error: %s\n",
                 sg::io::printable(message, std::string::npos).c_str());
}

// A usage error: the message (prefixed by the subcommand), a pointer to the
// subcommand's --help, and kExitUsage.
int usageError(const CLI::App& app, const std::string& message) {
    const std::string command = selectedCommand(app);
    // Messages of the subcommands start with their name already.
    const std::string first = command.substr(0, command.find(' '));
    const bool prefixed = !command.empty() && message.rfind(first, 0) != 0;
    printError((prefixed ? command + ": " : std::string()) + message);
    std::fprintf(stderr, "Run 'surfgrad %s%s--help' for usage.\n", command.c_str(),
                 command.empty() ? "" : " ");
    return sg::cli::kExitUsage;
}

// Every floating-point option of `app` and its subcommands (CLI11 type
// "FLOAT", also inside lists) takes finite values that a float can hold:
// "nan", "inf" and "1e39" are a usage error naming the option, where they
// would otherwise become a NaN image or a flat map with exit status 0.
void requireFiniteFloats(CLI::App& app) {
    const CLI::Validator finite(
        [](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (end == text.c_str()) return {}; // not a number: CLI11's own message
            if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max()))
                return "'" + text + "' is not a finite number a float can hold";
            return {};
        },
        "FINITE");
    for (CLI::Option* opt : app.get_options()) {
        if (opt->get_type_name().find("FLOAT") != std::string::npos) opt->check(finite);
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        requireFiniteFloats(*sub);
}

// A word where a command is expected that names none ("surfgrad frobnicate",
// "surfgrad mesh frobnicate"), which CLI11 reports only as "A subcommand is
// required": the usage error naming the word and the commands there, in the
// format of the others (usageError). Returns 0 when every word before the
// first option names a command.
int unknownCommand(const CLI::App& app, int argc, char** argv) {
    const CLI::App* at = &app;
    std::string path;
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        const auto subs = at->get_subcommands([](const CLI::App*) { return true; });
        if (word.empty() || word[0] == '-' || subs.empty()) return 0;
        const CLI::App* next = nullptr;
        std::string names;
        for (const CLI::App* sub : subs) {
            if (sub->check_name(word)) next = sub;
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!next) {
            printError((path.empty() ? std::string() : path + ": ") + "'" + word +
                       "' is not a command (commands: " + names + ")");
            std::fprintf(stderr, "Run 'surfgrad %s%s--help' for usage.\n", path.c_str(),
                         path.empty() ? "" : " ");
            return sg::cli::kExitUsage;
        }
        path += (path.empty() ? "" : " ") + next->get_name();
        at = next;
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"surfgrad: surface-gradient bump mapping on subdivision meshes"};
    app.set_version_flag("--version", std::string("surfgrad ") + SURFGRAD_VERSION +
                                          " (shader library v" +
                                          std::to_string(sg::kBumpLibraryVersion) + ")");
    app.require_subcommand(1);
    // Options of the top level are accepted after the subcommand too.
    app.fallthrough();
    // Option callbacks run before any subcommand's work starts.
    app.add_flag_callback(
        "--allow-outside-uris", [] { sg::mesh::setAllowOutsideFolderDefault(true); },
        "Let glTF buffer and image URIs resolve outside the model's folder (\"..\", "
        "absolute paths, symbolic links out of it); refused by default, so a model "
        "from elsewhere cannot read other files");
    int status = 0;
    sg::cli::addEvalCommand(app, status);
    sg::cli::addSelftestCommand(app, status);
    sg::cli::addRenderCommands(app, status);
    CLI::App* meshGroup =
        sg::cli::addMeshCommands(app, status); // more mesh subcommands attach here
    sg::cli::addMeshTangentsCommand(*meshGroup, status);
    sg::cli::describeMeshGroup(*meshGroup);
    sg::cli::addFeaturesCommands(app, status);
    sg::cli::addNormalmapCommands(app, status);
    sg::cli::addBakeCommand(app, status);
    addFooter(app);
    requireFiniteFloats(app);
    if (const int usage = unknownCommand(app, argc, argv); usage != 0) return usage;
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e); // --help, --version
    } catch (const CLI::ParseError& e) {
        return usageError(app, e.what());
    } catch (const sg::cli::CliError& e) {
        return usageError(app, e.what());
    } catch (const std::bad_alloc&) {
        // Loaders check declared sizes against limits and the texture
        // budget before they allocate, and name the input when memory runs
        // out all the same; this is the last line for anything else.
        std::string args;
        for (int i = 1; i < argc; ++i) args += std::string(i > 1 ? " " : "") + argv[i];
        printError("out of memory (std::bad_alloc) running `surfgrad " + args +
                   "`: an input declares more data than this machine can hold");
        return sg::cli::kExitFailure;
    } catch (const std::exception& e) {
        printError(e.what());
        return sg::cli::kExitFailure;
    }
    return status;
}
