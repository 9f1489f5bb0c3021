// `surfgrad normalmap ...`: the height-field-correct normal-map operations
// of Loviscach, "Care and Feeding of Normal Vectors" (GDC 2008) on image
// files, each also runnable --naive (the plain image operation) for
// comparison. The library is normalmap (surfgrad/normalmap/operations.h); every
// op and option is described in docs/normalmap.md.
//
//   normalmap from-height H -o OUT [--scale S] [--channel C]
//   normalmap to-height N -o OUT
//   normalmap to-derivative N -o OUT [--range R]
//   normalmap convert N -o OUT [--to ENC] [--to-green G] [--mesh M --uv-set K]
//   normalmap scale N -o OUT --alpha A
//   normalmap add A B -o OUT [--weights WA,WB]
//   normalmap blend A B --mask M -o OUT [--mask-channel C]
//   normalmap modulate N --by G -o OUT [--gain K] [--by-channel C]
//   normalmap curves N -o OUT (--boost P,H | --points "x,y ..." | --points-file F)
//   normalmap deform N -o OUT --warp sine:A,B|rotate:DEG
//   normalmap mips N -o OUT.exr (--lean | --toksvig | --naive)
//   normalmap shade N -o OUT.png [--light X,Y,Z]
// Common options: --encoding/--green (how input maps are stored; default
// rgb, gl), --to/--to-green (output; default: as the input), --bits,
// --range (integer derivative maps), --wrap (the image tiles), --naive,
// --height-channel/--height-scale (heights stored in the map instead of
// integrated), --threads N, --progress. Outputs are written atomically and
// never over an input; errors print `surfgrad: error: file: element: reason`
// and exit 1.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "surfgrad/image/image_format.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/normalmap/operations.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::cli {

namespace fs = std::filesystem;
namespace nm = sg::normalmap;

namespace {

struct Options {
    std::string op;
    std::vector<std::string> inputs; // positional maps (1 or 2)
    std::string output;
    std::string encoding = "rgb", green = "gl", to, toGreen, bits;
    float range = 8.0f;
    bool wrap = false, naive = false, progress = false;
    int threads = 0;
    int heightChannel = -1;
    float heightScale = 1.0f;
    // Op parameters.
    float scale = 1.0f, alpha = 1.0f, gain = 1.0f;
    int channel = -1, maskChannel = -1, byChannel = -1;
    std::string weights = "1,1", mask, by, boost, points, pointsFile, warp;
    std::string mesh;
    int uvSet = 0, dilate = 4;
    bool lean = false, toksvig = false;
    std::string light = "-0.5,0.5,0.7";
    int level = -1;
};

nm::Wrap wrapOf(const Options& o) {
    return o.wrap ? nm::Wrap::Repeat : nm::Wrap::Clamp;
}

// Progress on stderr: with --progress, or when stderr is a terminal.
struct Reporter {
    std::string what;
    bool on = false;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    int last = -1;
    nm::Progress stage(const std::string& name) {
        if (!on) return {};
        return [this, name](double f) {
            const int pct = int(std::lround(100.0 * f));
            if (pct == last && pct != 100) return;
            last = pct;
            std::fprintf(stderr, "surfgrad: normalmap %s: %s %3d%%\n", what.c_str(), name.c_str(),
                         pct);
            if (pct == 100) last = -1;
        };
    }
    void note(const std::string& s) const {
        if (on) std::fprintf(stderr, "surfgrad: normalmap %s: %s\n", what.c_str(), s.c_str());
    }
};

std::vector<float> parseFloats(const std::string& text, size_t count, const std::string& option) {
    std::vector<float> v;
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t comma = text.find(',', pos);
        if (comma == std::string::npos) comma = text.size();
        float x = 0.0f;
        auto [p, ec] = std::from_chars(text.data() + pos, text.data() + comma, x);
        if (ec != std::errc() || p != text.data() + comma || !std::isfinite(x)) {
            throw CliError("normalmap: " + option + " expects " + std::to_string(count) +
                           " comma-separated numbers, got '" + text + "'");
        }
        v.push_back(x);
        pos = comma + 1;
    }
    if (v.size() != count) {
        throw CliError("normalmap: " + option + " expects " + std::to_string(count) +
                       " comma-separated numbers, got '" + text + "'");
    }
    return v;
}

// A map read from a file with its encoding.
struct Map {
    std::string file;
    nm::Image image;
    nm::SampleType type = nm::SampleType::U8;
    nm::MapFormat format;
};

Map readMap(const std::string& file, const Options& o) {
    Map m;
    m.file = file;
    m.image = nm::readImage(file, &m.type);
    // Object-space maps (convert --mesh) are stored as rgb.
    m.format.encoding = o.encoding == "object" ? nm::Encoding::Rgb : nm::parseEncoding(o.encoding);
    m.format.green = nm::parseGreen(o.green);
    m.format.derivRange = o.range;
    return m;
}

void requireSameSize(const Map& a, const nm::Image& b, const std::string& bFile) {
    if (a.image.width != b.width || a.image.height != b.height) {
        throw io::InputError(
            bFile, "size",
            std::to_string(b.width) + "x" + std::to_string(b.height) + " does not match " + a.file +
                " (" + std::to_string(a.image.width) + "x" + std::to_string(a.image.height) + ")");
    }
}

// The output's encoding (--to/--to-green, else the input's) and sample type
// (--bits, else by extension; float data forces float).
struct OutFormat {
    nm::MapFormat format;
    nm::SampleType type;
};

OutFormat outFormat(const Options& o, const nm::MapFormat& in) {
    OutFormat f;
    f.format = in;
    if (!o.to.empty()) f.format.encoding = nm::parseEncoding(o.to);
    if (!o.toGreen.empty()) f.format.green = nm::parseGreen(o.toGreen);
    f.format.derivRange = o.range;
    f.type = nm::mapSampleType(o.output, f.format, o.bits);
    const bool isFloat = f.type == nm::SampleType::Half || f.type == nm::SampleType::Float;
    if (f.format.encoding == nm::Encoding::Deriv && !isFloat) {
        // Integer derivative maps hold +-range at full scale.
        if (!(o.range > 0.0f)) throw CliError("normalmap: --range must be positive");
    }
    return f;
}

bool isFloatType(nm::SampleType t) {
    return t == nm::SampleType::Half || t == nm::SampleType::Float;
}

std::vector<std::pair<std::string, std::string>> attrs(const Options& o, const OutFormat& f) {
    std::vector<std::pair<std::string, std::string>> a = {
        {"surfgrad:op", o.op + (o.naive ? " --naive" : "")},
        {"surfgrad:encoding", std::string(nm::encodingName(f.format.encoding))},
        {"surfgrad:green", f.format.green == nm::Green::Gl ? "gl" : "dx"}};
    if (f.format.encoding == nm::Encoding::Deriv && !isFloatType(f.type)) {
        a.emplace_back("surfgrad:derivRange", std::to_string(f.format.derivRange));
    }
    return a;
}

void report(const Options& o, const nm::Image& img, const OutFormat& f) {
    std::printf("wrote %s (%dx%d, %s, %s green%s)\n", o.output.c_str(), img.width, img.height,
                std::string(nm::encodingName(f.format.encoding)).c_str(),
                f.format.green == nm::Green::Gl ? "gl" : "dx", o.naive ? ", naive" : "");
}

void writeSlopes(const Options& o, const nm::DerivField& d, const nm::MapFormat& in) {
    const OutFormat f = outFormat(o, in);
    const nm::Image img = nm::encodeSlopes(d, f.format, isFloatType(f.type));
    nm::writeImage(o.output, img, f.type, attrs(o, f));
    report(o, img, f);
}

void writeNormals(const Options& o, const nm::NormalField& n, const nm::MapFormat& in) {
    const OutFormat f = outFormat(o, in);
    const nm::Image img = nm::encodeNormals(n, f.format, isFloatType(f.type));
    nm::writeImage(o.output, img, f.type, attrs(o, f));
    report(o, img, f);
}

// Heights of a map: its height channel (--height-channel) or the Poisson
// solve of its slopes.
nm::ScalarField heightsOf(const Map& m, const nm::DerivField& d, const Options& o, Reporter& r) {
    if (o.heightChannel >= 0) {
        return nm::scalarFromImage(m.image, o.heightChannel, o.heightScale, m.file);
    }
    r.note("integrating the heights of " + m.file);
    return nm::toHeight(d, wrapOf(o), r.stage("to-height " + fs::path(m.file).filename().string()));
}

nm::ScalarField scalarInput(const std::string& file, int channel, float scale, const Map& like) {
    const nm::Image img = nm::readImage(file);
    requireSameSize(like, img, file);
    return nm::scalarFromImage(img, channel, scale, file);
}

nm::Curve curveOf(const Options& o) {
    const int given = int(!o.boost.empty()) + int(!o.points.empty()) + int(!o.pointsFile.empty());
    if (given != 1)
        throw CliError("normalmap curves: give exactly one of --boost, --points, --points-file");
    if (!o.boost.empty()) {
        const auto v = parseFloats(o.boost, 2, "--boost P,H");
        if (v[0] < 0.0f) throw CliError("normalmap curves: --boost P must be >= 0");
        return nm::boostCurve(v[0], v[1]);
    }
    if (!o.points.empty()) return nm::parseCurvePoints(o.points, "--points");
    return nm::parseCurvePoints(io::readFile(o.pointsFile, 1 << 20), o.pointsFile);
}

} // namespace

// The ops, one function each (run() dispatches).
namespace {

void runFromHeight(const Options& o, Reporter&) {
    const nm::Image img = nm::readImage(o.inputs[0]);
    const nm::ScalarField h = nm::scalarFromImage(img, o.channel, 1.0f, o.inputs[0]);
    const nm::DerivField d = o.naive ? nm::naive::fromHeight(h, o.scale, wrapOf(o))
                                     : nm::fromHeight(h, o.scale, wrapOf(o));
    nm::MapFormat base;
    base.green = nm::parseGreen(o.green);
    writeSlopes(o, d, base);
}

void runToHeight(const Options& o, Reporter& r) {
    const Map m = readMap(o.inputs[0], o);
    const nm::DerivField d = nm::decodeSlopes(m.image, m.format, m.file);
    const nm::ScalarField h =
        o.naive ? nm::naive::toHeight(d) : nm::toHeight(d, wrapOf(o), r.stage("integrating"));
    float hi = 0.0f;
    for (float x : h.v) hi = std::max(hi, x);
    const nm::SampleType type =
        o.bits.empty() ? nm::defaultSampleType(o.output, false) : nm::parseSampleType(o.bits);
    const bool isFloat = isFloatType(type);
    // Float files hold texels of height; integer files height / range, so
    // `from-height OUT --scale range` gives the map back.
    const float unit = isFloat || hi <= 0.0f ? 1.0f : 1.0f / hi;
    nm::writeImage(o.output, nm::imageFromScalar(h, 0.0f, unit, isFloat), type,
                   {{"surfgrad:op", o.op + (o.naive ? " --naive" : "")},
                    {"surfgrad:heightTexelsPerUnit", std::to_string(1.0f / unit)}});
    std::printf("wrote %s (%dx%d height, 0 to %.6g texels%s; from-height --scale %.6g restores "
                "the slopes)\n",
                o.output.c_str(), h.width, h.height, double(hi),
                isFloat ? ", stored in texels" : ", stored as height / range", double(1.0f / unit));
}

void runConvert(const Options& o, Reporter& r) {
    const Map m = readMap(o.inputs[0], o);
    if (o.mesh.empty()) {
        if (o.naive) {
            // Slopes read as -n.xy (or n.xy as -d): the small-angle reading.
            const nm::NormalField n = nm::decodeNormals(m.image, m.format, m.file);
            writeSlopes(o, nm::naive::slopesFromNormals(n), m.format);
        } else {
            writeSlopes(o, nm::decodeSlopes(m.image, m.format, m.file), m.format);
        }
        return;
    }
    // Object space: --encoding object (object -> tangent) or --to object.
    const bool fromObject = o.encoding == "object", toObject = o.to == "object";
    if (fromObject == toObject) {
        throw CliError("normalmap convert --mesh: give --encoding object (object-space input) or "
                       "--to object (object-space output)");
    }
    r.note("rasterising the UV layout of " + o.mesh);
    const auto mesh = sg::mesh::loadRenderMesh(o.mesh);
    if (o.uvSet < 0 || size_t(o.uvSet) >= mesh.uvSets.size()) {
        throw io::InputError(o.mesh, "uv set " + std::to_string(o.uvSet),
                             "the mesh has " + std::to_string(mesh.uvSets.size()) + " UV set(s)");
    }
    if (mesh.normals.size() != mesh.positions.size()) {
        throw io::InputError(o.mesh, "normals", "the mesh has no vertex normals");
    }
    const nm::TexelFrames frames =
        nm::rasterizeFrames(mesh, o.uvSet, m.image.width, m.image.height, o.dilate);
    nm::MapFormat objFormat; // object maps: rgb 0.5 n + 0.5, no green convention
    Options out = o;
    if (toObject) {
        const nm::DerivField d = nm::decodeSlopes(m.image, m.format, m.file);
        const nm::NormalField obj =
            o.naive ? nm::naive::objectFromTangent(nm::normalsFromSlopes(d), frames)
                    : nm::objectFromTangent(d, frames);
        out.to = "rgb";
        out.toGreen = "gl";
        writeNormals(out, obj, objFormat);
        return;
    }
    if (m.image.channels < 3) {
        throw io::InputError(m.file, "channels", "an object-space map needs 3 channels");
    }
    const nm::NormalField obj = nm::decodeNormals(m.image, objFormat, m.file);
    nm::MapFormat tangent;
    tangent.green = nm::parseGreen(o.green);
    if (out.to.empty()) out.to = "rgb";
    if (o.naive) {
        writeNormals(out, nm::naive::tangentFromObject(obj, frames), tangent);
    } else {
        writeSlopes(out, nm::tangentFromObject(obj, frames), tangent);
    }
}

void runScale(const Options& o, Reporter&) {
    const Map m = readMap(o.inputs[0], o);
    if (o.naive) {
        writeNormals(o, nm::naive::scale(nm::decodeNormals(m.image, m.format, m.file), o.alpha),
                     m.format);
    } else {
        writeSlopes(o, nm::scale(nm::decodeSlopes(m.image, m.format, m.file), o.alpha), m.format);
    }
}

void runAdd(const Options& o, Reporter&) {
    const Map a = readMap(o.inputs[0], o), b = readMap(o.inputs[1], o);
    requireSameSize(a, b.image, b.file);
    const auto w = parseFloats(o.weights, 2, "--weights WA,WB");
    if (o.naive) {
        writeNormals(o,
                     nm::naive::add(nm::decodeNormals(a.image, a.format, a.file), w[0],
                                    nm::decodeNormals(b.image, b.format, b.file), w[1]),
                     a.format);
    } else {
        writeSlopes(o,
                    nm::add(nm::decodeSlopes(a.image, a.format, a.file), w[0],
                            nm::decodeSlopes(b.image, b.format, b.file), w[1]),
                    a.format);
    }
}

void runBlend(const Options& o, Reporter& r) {
    if (o.mask.empty()) throw CliError("normalmap blend: --mask M is required");
    const Map a = readMap(o.inputs[0], o), b = readMap(o.inputs[1], o);
    requireSameSize(a, b.image, b.file);
    const nm::ScalarField mask = scalarInput(o.mask, o.maskChannel, 1.0f, a);
    if (o.naive) {
        writeNormals(o,
                     nm::naive::blend(nm::decodeNormals(a.image, a.format, a.file),
                                      nm::decodeNormals(b.image, b.format, b.file), mask),
                     a.format);
        return;
    }
    const nm::DerivField da = nm::decodeSlopes(a.image, a.format, a.file);
    const nm::DerivField db = nm::decodeSlopes(b.image, b.format, b.file);
    const nm::ScalarField ha = heightsOf(a, da, o, r), hb = heightsOf(b, db, o, r);
    writeSlopes(o, nm::blend(da, ha, db, hb, mask, wrapOf(o)), a.format);
}

void runModulate(const Options& o, Reporter& r) {
    if (o.by.empty()) throw CliError("normalmap modulate: --by G is required");
    const Map m = readMap(o.inputs[0], o);
    const nm::ScalarField gain = scalarInput(o.by, o.byChannel, o.gain, m);
    if (o.naive) {
        writeNormals(o, nm::naive::modulate(nm::decodeNormals(m.image, m.format, m.file), gain),
                     m.format);
        return;
    }
    const nm::DerivField d = nm::decodeSlopes(m.image, m.format, m.file);
    writeSlopes(o, nm::modulate(d, heightsOf(m, d, o, r), gain, wrapOf(o)), m.format);
}

void runCurves(const Options& o, Reporter& r) {
    const nm::Curve curve = curveOf(o);
    const Map m = readMap(o.inputs[0], o);
    const nm::DerivField d = nm::decodeSlopes(m.image, m.format, m.file);
    const nm::ScalarField h = heightsOf(m, d, o, r);
    if (o.naive) {
        writeNormals(o,
                     nm::naive::applyCurve(nm::decodeNormals(m.image, m.format, m.file), h, curve),
                     m.format);
    } else {
        writeSlopes(o, nm::applyCurve(d, h, curve), m.format);
    }
}

void runDeform(const Options& o, Reporter&) {
    if (o.warp.empty())
        throw CliError("normalmap deform: --warp sine:A,B or rotate:DEG is required");
    const nm::Warp warp = nm::parseWarp(o.warp);
    const Map m = readMap(o.inputs[0], o);
    if (o.naive) {
        writeNormals(
            o, nm::naive::deform(nm::decodeNormals(m.image, m.format, m.file), warp, wrapOf(o)),
            m.format);
    } else {
        writeSlopes(o, nm::deform(nm::decodeSlopes(m.image, m.format, m.file), warp, wrapOf(o)),
                    m.format);
    }
}

void runMips(const Options& o, Reporter& r) {
    if (int(o.lean) + int(o.toksvig) + int(o.naive) != 1) {
        throw CliError("normalmap mips: give exactly one of --lean, --toksvig, --naive");
    }
    const std::string ext = image::lowerExtension(o.output);
    if (ext != ".exr") {
        throw CliError("normalmap mips: -o " + o.output +
                       ": a MIP chain is written as OpenEXR (.exr), one part per level");
    }
    const Map m = readMap(o.inputs[0], o);
    std::vector<nm::Image> levels;
    std::string layout;
    if (o.lean) {
        layout = nm::kLeanLayout;
        levels = nm::mipChain(nm::leanLevel0(nm::decodeSlopes(m.image, m.format, m.file)),
                              r.stage("filtering"));
    } else {
        layout = o.toksvig ? nm::kToksvigLayout : nm::kNaiveMipLayout;
        const nm::NormalField n = nm::decodeNormals(m.image, m.format, m.file);
        levels = nm::mipChain(o.toksvig ? nm::toksvigLevel0(n) : nm::naiveMipLevel0(n),
                              r.stage("filtering"));
        if (o.toksvig)
            nm::finishToksvig(levels);
        else
            nm::finishNaiveMips(levels);
    }
    nm::writeMipChain(o.output, levels, nm::mipChannelNames(layout), layout, wrapOf(o));
    std::printf("wrote %s (%s, %zu levels from %dx%d)\n", o.output.c_str(), layout.c_str(),
                levels.size(), m.image.width, m.image.height);
}

// A MIP level of a chain file as shading normals: Toksvig's average normal
// as stored (unnormalised: its Lambert term is the average of the texels'
// Lambert terms wherever they face the light), a naive chain's renormalised
// one, LEAN's mean slope as a normal.
nm::NormalField mipLevelNormals(const Options& o) {
    std::string layout;
    const auto levels = nm::readMipChain(o.inputs[0], nullptr, &layout);
    if (o.level < 0 || size_t(o.level) >= levels.size()) {
        throw io::InputError(o.inputs[0], "level " + std::to_string(o.level),
                             "the chain has " + std::to_string(levels.size()) + " levels");
    }
    const nm::Image& L = levels[size_t(o.level)];
    if (layout == nm::kLeanLayout) {
        nm::DerivField d(L.width, L.height);
        for (int j = 0; j < L.height; ++j)
            for (int i = 0; i < L.width; ++i) d.at(i, j) = glm::vec2(L.at(i, j, 0), L.at(i, j, 1));
        return nm::normalsFromSlopes(d);
    }
    if (layout != nm::kToksvigLayout && layout != nm::kNaiveMipLayout) {
        throw io::InputError(o.inputs[0], "surfgrad:layout", "not a MIP chain of `normalmap mips`");
    }
    nm::NormalField n(L.width, L.height);
    for (int j = 0; j < L.height; ++j)
        for (int i = 0; i < L.width; ++i)
            n.at(i, j) = glm::vec3(L.at(i, j, 0), L.at(i, j, 1), L.at(i, j, 2));
    return n;
}

void runShade(const Options& o, Reporter&) {
    const auto l = parseFloats(o.light, 3, "--light X,Y,Z");
    nm::NormalField n;
    if (o.level >= 0) {
        n = mipLevelNormals(o);
    } else {
        const Map m = readMap(o.inputs[0], o);
        n = nm::decodeNormals(m.image, m.format, m.file);
    }
    const nm::Image img = nm::shade(n, glm::vec3(l[0], l[1], l[2]));
    nm::writeImage(o.output, img,
                   o.bits.empty() ? nm::defaultSampleType(o.output, false)
                                  : nm::parseSampleType(o.bits));
    std::printf("wrote %s (%dx%d, Lambert shading)\n", o.output.c_str(), img.width, img.height);
}

void run(Options o) {
    std::vector<fs::path> ins(o.inputs.begin(), o.inputs.end());
    for (const std::string* extra : {&o.mask, &o.by, &o.pointsFile, &o.mesh}) {
        if (!extra->empty()) ins.emplace_back(*extra);
    }
    if (!o.output.empty()) io::checkOutputPath(o.output);
    for (const fs::path& in : ins) io::checkNotInput(o.output, {in});
    if ((o.encoding == "object" || o.to == "object") && (o.op != "convert" || o.mesh.empty())) {
        throw CliError("normalmap " + o.op + ": object-space maps need `convert --mesh M`");
    }
    const auto threadLimit = limitThreads(o.threads);
    Reporter r;
    r.what = o.op;
    r.on = o.progress || ::isatty(2);
    if (o.op == "from-height")
        runFromHeight(o, r);
    else if (o.op == "to-height")
        runToHeight(o, r);
    else if (o.op == "to-derivative") {
        o.to = "deriv";
        runConvert(o, r);
    } else if (o.op == "convert")
        runConvert(o, r);
    else if (o.op == "scale")
        runScale(o, r);
    else if (o.op == "add")
        runAdd(o, r);
    else if (o.op == "blend")
        runBlend(o, r);
    else if (o.op == "modulate")
        runModulate(o, r);
    else if (o.op == "curves")
        runCurves(o, r);
    else if (o.op == "deform")
        runDeform(o, r);
    else if (o.op == "mips")
        runMips(o, r);
    else
        runShade(o, r);
}

// Options every op takes.
void addCommon(CLI::App* c, Options& o, bool readsMap) {
    c->add_option("-o,--output", o.output, "Output image")->required();
    if (readsMap) {
        c->add_option("--encoding", o.encoding,
                      "How the input map is stored: rgb (default), rg, ag, signed, deriv");
        c->add_option("--green", o.green, "Input green convention: gl (+v up, default) or dx");
    }
    c->add_option("--to", o.to, "Output encoding (default: as the input)");
    c->add_option("--to-green", o.toGreen,
                  readsMap ? "Output green convention (default: as the input)"
                           : "Output green convention: gl (+v up, default) or dx");
    c->add_option("--bits", o.bits, "Output samples: 8, 16, half or float (default by extension)");
    c->add_option("--range", o.range, "Slope at full scale of integer derivative maps (default 8)");
    c->add_flag("--wrap", o.wrap, "The image tiles (periodic differences, sampling, integration)");
    c->add_flag("--naive", o.naive, "The plain image operation instead (for comparison)");
    addThreadsOption(c, o.threads);
    c->add_flag("--progress", o.progress, "Report progress on stderr (default: when a terminal)");
}

void addHeightOptions(CLI::App* c, Options& o) {
    c->add_option("--height-channel", o.heightChannel,
                  "Read heights from this channel of the map (default: integrate the slopes)");
    c->add_option("--height-scale", o.heightScale,
                  "Texels of height per unit of --height-channel (default 1)");
}

} // namespace

void addNormalmapCommands(CLI::App& app, int& status) {
    auto* group = app.add_subcommand(
        "normalmap", "Height-field-correct normal-map operations on images (Loviscach 2008)");
    group->require_subcommand(1);
    auto add = [&](const char* name, const char* help, int maps, bool readsMap) {
        auto o = std::make_shared<Options>();
        o->op = name;
        auto* c = group->add_subcommand(name, help);
        c->add_option("inputs", o->inputs, maps == 2 ? "Maps A and B" : "Input image")
            ->required()
            ->expected(maps);
        addCommon(c, *o, readsMap);
        c->callback([o] { run(*o); });
        return std::make_pair(c, o);
    };
    {
        auto [c, o] =
            add("from-height", "Normal map of a height image (central differences)", 1, false);
        c->add_option("--scale", o->scale,
                      "Texels of height per unit of the image value (default 1)");
        c->add_option("--channel", o->channel, "Height channel (default: luminance or channel 0)");
    }
    add("to-height", "Height of a normal map (least-squares Poisson solve)", 1, true);
    add("to-derivative", "Derivative map (dh/du, dh/dv) of a normal map", 1, true);
    {
        auto [c, o] = add(
            "convert", "Between encodings, green conventions, tangent and object space", 1, true);
        c->add_option("--mesh", o->mesh,
                      "Mesh whose UV layout and frames the map belongs to (object space)");
        c->add_option("--uv-set", o->uvSet, "UV set of the mesh (default 0)");
        c->add_option("--dilate", o->dilate, "Texels filled past UV island borders (default 4)");
    }
    {
        auto [c, o] = add("scale", "Slopes of alpha h (alpha = -1 inverts)", 1, true);
        c->add_option("--alpha", o->alpha, "Height factor alpha")->required();
    }
    {
        auto [c, o] = add("add", "Slopes of wa hA + wb hB", 2, true);
        c->add_option("--weights", o->weights, "wa,wb (default 1,1)");
    }
    {
        auto [c, o] = add("blend", "Slopes of (1 - m) hA + m hB for a mask m", 2, true);
        c->add_option("--mask", o->mask, "Mask image m in [0, 1]")->required();
        c->add_option("--mask-channel", o->maskChannel, "Mask channel (default: luminance or 0)");
        addHeightOptions(c, *o);
    }
    {
        auto [c, o] = add("modulate", "Slopes of h g for a gain image g", 1, true);
        c->add_option("--by", o->by, "Gain image g")->required();
        c->add_option("--by-channel", o->byChannel, "Gain channel (default: luminance or 0)");
        c->add_option("--gain", o->gain, "Multiplies the gain image (default 1)");
        addHeightOptions(c, *o);
    }
    {
        auto [c, o] = add("curves", "A curve f applied to the elevation: slopes f'(x) d", 1, true);
        c->add_option("--boost", o->boost, "P,H: f'(x) = 1 / (1 + P (x - H)^2) (the paper's)");
        c->add_option("--points", o->points, "\"x,y x,y ...\": monotone cubic through the points");
        c->add_option("--points-file", o->pointsFile, "File with the points");
        addHeightOptions(c, *o);
    }
    {
        auto [c, o] = add("deform", "h(warp(u, v)) through the warp's Jacobian", 1, true);
        c->add_option("--warp", o->warp, "sine:A,B (t = v + A sin(B u)) or rotate:DEG")->required();
    }
    {
        auto [c, o] = add("mips", "MIP chain for antialiasing (OpenEXR)", 1, true);
        c->add_flag("--lean", o->lean, "LEAN moments: dx dy dxx dyy dxy");
        c->add_flag("--toksvig", o->toksvig, "Toksvig: average normal and variance");
    }
    {
        auto [c, o] = add("shade", "Lambert-shaded preview of a map", 1, true);
        c->add_option("--light", o->light,
                      "Light direction x,y,z in tangent space (default -0.5,0.5,0.7)");
        c->add_option("--level", o->level, "Shade this level of a `mips` chain file instead");
    }
    (void)status;
}

} // namespace sg::cli
