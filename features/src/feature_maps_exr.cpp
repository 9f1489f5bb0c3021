// OpenEXR storage of baked feature maps (layout: surfgrad/features/feature_maps.h).
// Loading treats the file as untrusted: sizes are checked before anything
// is allocated, every channel and metadata field must be present with the
// right type, every value must be finite and in range, configurations must
// be consistent with the edge points, and in quadratic mode every curved
// segment's signature must pass the same validation the bake applies, so
// the runtime evaluator only ever sees data it was designed for. The file
// is read by the image module's decoder (surfgrad/image/image_decode.h) and
// written by its writer (surfgrad/image/image_write.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <variant>

#include "bake_internal.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/image/image_decode.h"
#include "surfgrad/image/image_header.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"

namespace sg::features {

namespace {

const char* kLayout =
    "surfgrad feature maps: (N+1)^2 grid corners, scanline 0 = top (j = N); d,gx,gy,left per "
    "corner; "
    "seg = configuration bits 0-11 of texel (i,j); hT,hA / vT,vA = point on edge (i,j)-(i+1,j) / "
    "(i,j)-(i,j+1), T = -1 without a point; see surfgrad/features/feature_maps.h";

std::vector<std::string> channelNames() {
    return {"d", "gx", "gy", "left", "seg", "hT", "vT", "hA", "vA"};
}

std::string pixelName(int i, int j) {
    return "corner (" + std::to_string(i) + ", " + std::to_string(j) + ")";
}

// Floats per piece in surfgrad:nearPieces: p0, p1, p2 (x, y), curved (0/1),
// profile (-1 or a table index), width0, width1.
constexpr int kPieceFloats = 10;

// The metadata value `key` of the file when it has the type T (int,
// double, std::string, std::vector<float>); nullptr when absent or of
// another type. `present` tells the two apart.
template <class T>
const T* attribute(const image::DecodedImage& file, const std::string& key,
                   bool* present = nullptr) {
    const auto it = file.attributes.find(key);
    if (present) *present = it != file.attributes.end();
    return it == file.attributes.end() ? nullptr : std::get_if<T>(&it->second);
}

// The exact near field's metadata, when present (every value checked: the
// runtime only ever sees pieces the bake could have written).
void readNearField(const image::DecodedImage& file, const std::string& name, FeatureMaps& m) {
    using io::InputError;
    bool present = false;
    const double* band = attribute<double>(file, "surfgrad:nearBandTexels", &present);
    if (!present) return;
    const double b = band ? *band : 0.0;
    if (!(b > 0.0 && b <= m.bandTexels && b <= kMaxNearBandTexels)) {
        throw InputError(name, "metadata surfgrad:nearBandTexels",
                         "must be a double in (0, min(bandTexels, " +
                             std::to_string(int(kMaxNearBandTexels)) + ")]");
    }
    m.nearBandTexels = b;
    // The profile table (';'-separated makeProfile names; absent: empty).
    const std::string* profiles = attribute<std::string>(file, "surfgrad:nearProfiles", &present);
    if (present && !profiles)
        throw InputError(name, "metadata surfgrad:nearProfiles", "not a string");
    const std::string table = profiles ? *profiles : "";
    for (size_t at = 0; at < table.size();) {
        size_t end = std::min(table.find(';', at), table.size());
        std::string p = table.substr(at, end - at);
        try {
            (void)makeProfile(p, 1.0f, 0.0f, 1.0f);
        } catch (const InputError& e) {
            throw InputError(name, "metadata surfgrad:nearProfiles", e.reason());
        }
        if (std::find(m.profiles.begin(), m.profiles.end(), p) != m.profiles.end())
            throw InputError(name, "metadata surfgrad:nearProfiles", "profile '" + p + "' twice");
        m.profiles.push_back(p);
        if (m.profiles.size() > size_t(SG_FEAT_MAX_PROFILES))
            throw InputError(name, "metadata surfgrad:nearProfiles",
                             "more than " + std::to_string(SG_FEAT_MAX_PROFILES) + " profiles");
        at = end + 1;
    }
    const std::vector<float>* pieces = attribute<std::vector<float>>(file, "surfgrad:nearPieces");
    const size_t floats = pieces ? pieces->size() : 0;
    if (floats == 0 || floats % kPieceFloats != 0 ||
        floats / kPieceFloats > size_t(kMaxNearPieces)) {
        throw InputError(name, "metadata surfgrad:nearPieces",
                         "missing, or not a float array of 10 values per piece (at most " +
                             std::to_string(kMaxNearPieces) + " pieces)");
    }
    const float* v = pieces->data();
    const int count = int(floats / kPieceFloats);
    m.pieces.resize(size_t(count));
    for (int k = 0; k < count; ++k) {
        const float* f = v + size_t(k) * kPieceFloats;
        auto bad = [&](const std::string& why) {
            return InputError(name, "metadata surfgrad:nearPieces piece " + std::to_string(k), why);
        };
        for (int c = 0; c < kPieceFloats; ++c)
            if (!std::isfinite(f[c])) throw bad("not finite");
        for (int c = 0; c < 6; ++c)
            if (std::fabs(f[c]) > 1e6f)
                throw bad("coordinate more than 1e6 texels from the origin");
        NearPiece& p = m.pieces[size_t(k)];
        p.p0 = {f[0], f[1]};
        p.p1 = {f[2], f[3]};
        p.p2 = {f[4], f[5]};
        if (f[6] != 0.0f && f[6] != 1.0f) throw bad("curved flag must be 0 or 1");
        p.curved = f[6] == 1.0f;
        if (!p.curved && p.p1 != 0.5f * (p.p0 + p.p2))
            throw bad("a line's middle point must be its midpoint");
        if (p.p0 == p.p2) throw bad("coincident end points");
        if (f[7] != std::floor(f[7]) || f[7] < -1.0f || f[7] >= float(m.profiles.size()))
            throw bad("profile index outside the profile table");
        p.profile = int(f[7]);
        for (int c = 8; c < 10; ++c)
            if (f[c] < 0.0f || double(f[c]) > m.nearBandTexels)
                throw bad("profile width outside [0, near band]");
        p.width0 = f[8];
        p.width1 = f[9];
    }
    detail::checkNearFieldWork(m, name);
}

// The metadata: version, mode, size (and the image's), transform, band,
// smoothing, source.
FeatureMaps readMetadata(const image::DecodedImage& file, const std::string& name) {
    using io::InputError;
    auto intAttr = [&](const char* key) {
        const int* v = attribute<int>(file, key);
        if (!v) throw InputError(name, std::string("metadata ") + key, "missing or not an integer");
        return *v;
    };
    auto doubleAttr = [&](const char* key) {
        const double* v = attribute<double>(file, key);
        if (!v || !std::isfinite(*v)) {
            throw InputError(name, std::string("metadata ") + key,
                             "missing or not a finite double");
        }
        return *v;
    };
    auto stringAttr = [&](const char* key) {
        const std::string* v = attribute<std::string>(file, key);
        if (!v) throw InputError(name, std::string("metadata ") + key, "missing or not a string");
        return *v;
    };
    FeatureMaps m;
    int version = intAttr("surfgrad:featureMapsVersion");
    if (version != kFeatureMapsVersion) {
        throw InputError(name, "metadata surfgrad:featureMapsVersion",
                         "version " + std::to_string(version) + " (this build reads " +
                             std::to_string(kFeatureMapsVersion) + ")");
    }
    std::string mode = stringAttr("surfgrad:mode");
    if (mode == "linear")
        m.mode = BakeMode::Linear;
    else if (mode == "quadratic")
        m.mode = BakeMode::Quadratic;
    else
        throw InputError(name, "metadata surfgrad:mode",
                         "'" + mode + "' is neither linear nor quadratic");
    m.size = intAttr("surfgrad:size");
    if (m.size < 1 || m.size > kMaxFeatureMapSize) {
        throw InputError(name, "metadata surfgrad:size",
                         "must be 1.." + std::to_string(kMaxFeatureMapSize));
    }
    const int g = m.size + 1;
    // (The decoder reads images of depth 1 only.)
    if (file.width != g || file.height != g || file.originX != 0 || file.originY != 0) {
        throw InputError(name, "image",
                         "must be " + std::to_string(g) + " x " + std::to_string(g) +
                             " pixels (size + 1) at origin 0 with depth 1");
    }
    m.inputToTexel.scale = {doubleAttr("surfgrad:inputToTexelScaleX"),
                            doubleAttr("surfgrad:inputToTexelScaleY")};
    m.inputToTexel.offset = {doubleAttr("surfgrad:inputToTexelOffsetX"),
                             doubleAttr("surfgrad:inputToTexelOffsetY")};
    if (m.inputToTexel.scale.x == 0.0 || m.inputToTexel.scale.y == 0.0) {
        throw InputError(name, "metadata surfgrad:inputToTexelScale", "scale must be non-zero");
    }
    m.bandTexels = doubleAttr("surfgrad:bandTexels");
    if (!(m.bandTexels >= 1.0 && m.bandTexels <= 1024.0)) {
        throw InputError(name, "metadata surfgrad:bandTexels", "must be 1..1024");
    }
    m.smoothIterations = intAttr("surfgrad:smoothIterations");
    if (m.smoothIterations < 0 || m.smoothIterations > 1000) {
        throw InputError(name, "metadata surfgrad:smoothIterations", "must be 0..1000");
    }
    if (const std::string* source = attribute<std::string>(file, "surfgrad:source"))
        m.source = *source;
    return m;
}

// The corner channels: every value finite and in range, positions and
// angles on their 16-bit grids.
void readCorners(const image::DecodedImage& file, const std::string& name, FeatureMaps& m) {
    using io::InputError;
    const int g = m.size + 1;
    auto names = channelNames();
    if (file.fileChannels != int(names.size())) {
        throw InputError(name, "channels",
                         "expected " + std::to_string(names.size()) + " channels, found " +
                             std::to_string(file.fileChannels));
    }
    std::vector<int> slot(names.size(), -1);
    for (size_t c = 0; c < names.size(); ++c) {
        for (int k = 0; k < file.fileChannels; ++k) {
            if (file.channelNames[size_t(k)] == names[c]) slot[c] = k;
        }
        if (slot[c] < 0) throw InputError(name, "channel " + names[c], "missing");
        if (file.channelFormats[size_t(slot[c])] != "float") {
            throw InputError(name, "channel " + names[c], "must be 32-bit float");
        }
    }
    const size_t nc = size_t(g) * size_t(g);
    m.dist.resize(nc);
    m.gradX.resize(nc);
    m.gradY.resize(nc);
    m.left.resize(nc);
    m.seg.resize(nc);
    m.hPos.resize(nc);
    m.vPos.resize(nc);
    m.hAngle.assign(nc, 0.0f);
    m.vAngle.assign(nc, 0.0f);
    const double margin = double(SG_FEAT_EDGE_MARGIN);
    // Checked in file order, scanline 0 (the top, j = N) first; the
    // decoded samples are float, the bottom row first: corner (i, j) is
    // sample m.index(i, j).
    for (int row = 0; row < g; ++row) {
        int j = g - 1 - row;
        for (int i = 0; i < g; ++i) {
            size_t k = m.index(i, j);
            auto ch = [&](size_t c) {
                float v;
                std::memcpy(&v, &file.data[(k * names.size() + size_t(slot[c])) * sizeof(float)],
                            sizeof(float));
                return v;
            };
            auto bad = [&](const std::string& channel, const std::string& why) {
                return InputError(name, pixelName(i, j) + " channel " + channel, why);
            };
            for (size_t c = 0; c < names.size(); ++c) {
                if (!std::isfinite(ch(c))) throw bad(names[c], "not finite");
            }
            float d = ch(0), gx = ch(1), gy = ch(2), left = ch(3), seg = ch(4), hT = ch(5),
                  vT = ch(6);
            if (d < 0.0f || d > float(m.bandTexels) * 1.0001f) throw bad("d", "outside [0, band]");
            if (gx * gx + gy * gy > 1.0002f) throw bad("gx", "gradient longer than 1");
            if (left != 0.0f && left != 1.0f) throw bad("left", "must be 0 or 1");
            if (seg < 0.0f || seg > 4095.0f || seg != std::floor(seg))
                throw bad("seg", "not an integer in 0..4095");
            m.dist[k] = d;
            m.gradX[k] = gx;
            m.gradY[k] = gy;
            m.left[k] = uint8_t(left);
            m.seg[k] = uint16_t(seg);
            if ((i == m.size || j == m.size) && m.seg[k] != 0)
                throw bad("seg", "set outside the map (last row/column)");
            auto checkPos = [&](float t, bool exists, const char* chName) {
                if (t == -1.0f) return;
                if (!exists) throw bad(chName, "point on an edge outside the map");
                if (!(double(t) >= margin - 1e-7 && double(t) <= 1.0 - margin + 1e-7))
                    throw bad(chName, "position outside [2^-10, 1 - 2^-10]");
                if (std::fabs(double(t) - detail::quantizePos(double(t))) > 1e-6)
                    throw bad(chName, "position not on the 16-bit grid");
            };
            checkPos(hT, i < m.size, "hT");
            checkPos(vT, j < m.size, "vT");
            m.hPos[k] = hT;
            m.vPos[k] = vT;
            {
                float hA = ch(7), vA = ch(8);
                for (auto [a, t, chName] : {std::tuple{hA, hT, "hA"}, std::tuple{vA, vT, "vA"}}) {
                    if (std::fabs(a) > float(M_PI / 2) + 1e-6f)
                        throw bad(chName, "angle outside [-pi/2, pi/2]");
                    if (t == -1.0f && a != 0.0f) throw bad(chName, "angle without a point");
                    // Compared as line directions (mod pi): -pi/2 and pi/2 are one.
                    double off = detail::wrapAngle(double(a) - detail::quantizeAngle(double(a)));
                    if (std::fabs(off) > 1e-6) throw bad(chName, "angle not on the 16-bit grid");
                }
                m.hAngle[k] = hA;
                m.vAngle[k] = vA;
            }
        }
    }
}

// Configurations: counts, distinct segment types, end points present,
// curved only in quadratic mode, curved signatures valid (the bake's checks).
void checkConfigurations(const std::string& name, const FeatureMaps& m) {
    using io::InputError;
    const size_t nc = size_t(m.size + 1) * size_t(m.size + 1);
    detail::Grid grid;
    grid.n = m.size;
    grid.hPos.assign(nc, -1.0);
    grid.vPos.assign(nc, -1.0);
    grid.hAng.assign(nc, 0.0);
    grid.vAng.assign(nc, 0.0);
    for (size_t k = 0; k < nc; ++k) {
        grid.hPos[k] = m.hPos[k];
        grid.vPos[k] = m.vPos[k];
        grid.hAng[k] = m.hAngle[k];
        grid.vAng[k] = m.vAngle[k];
    }
    grid.segMask.assign(size_t(m.size) * size_t(m.size), 0);
    grid.quadMask.assign(size_t(m.size) * size_t(m.size), 0);
    grid.straightMask.assign(size_t(m.size) * size_t(m.size), 0);
    for (int j = 0; j < m.size; ++j) {
        for (int i = 0; i < m.size; ++i) {
            uint32_t w = m.seg[m.index(i, j)];
            auto bad = [&](const std::string& why) {
                return InputError(
                    name, "texel (" + std::to_string(i) + ", " + std::to_string(j) + ") seg", why);
            };
            int count = int(w & 3u);
            if (count > 2) throw bad("more than two segments");
            uint32_t used = (count == 0) ? 0x3u : (count == 1 ? 0x7Fu : 0xFFFu);
            if (w & ~used) throw bad("bits set for absent segments");
            size_t ti = grid.ti(i, j);
            for (int s = 0; s < count; ++s) {
                int a = int((w >> (2 + 5 * s)) & 3u), b = int((w >> (4 + 5 * s)) & 3u);
                bool curved = ((w >> (6 + 5 * s)) & 1u) != 0;
                int pair = detail::pairOf(a, b);
                if (pair < 0) throw bad("segment joins an edge to itself");
                if (detail::kPairEdges[pair][0] != a)
                    throw bad("segment end points not in canonical order");
                if (grid.segMask[ti] & (1u << pair)) throw bad("two identical segments");
                if (grid.pos(i, j, a) < 0.0 || grid.pos(i, j, b) < 0.0)
                    throw bad("segment ends on an edge without a point");
                if (curved && m.mode != BakeMode::Quadratic)
                    throw bad("curved segment in linear maps");
                grid.segMask[ti] |= uint8_t(1u << pair);
                if (curved) grid.quadMask[ti] |= uint8_t(1u << pair);
            }
            if (count == 2) {
                // Segments are stored in increasing type order (as the bake writes them).
                int a0 = int((w >> 2) & 3u), b0 = int((w >> 4) & 3u), a1 = int((w >> 7) & 3u),
                    b1 = int((w >> 9) & 3u);
                if (detail::pairOf(a0, b0) > detail::pairOf(a1, b1))
                    throw bad("segments not in canonical order");
            }
            if (grid.quadMask[ti]) {
                detail::LocalTexel t = detail::decodeTexel(grid, i, j);
                double viol = detail::validateTexel(t, nullptr);
                bool same = viol <= 0.0;
                for (int s = 0; s < t.nseg; ++s) same = same && (t.curved[s] == t.candidate[s]);
                if (!same)
                    throw bad("curved segment with an invalid signature (TOG 2008 sec. 4-5)");
            }
        }
    }
}

// The file decoded by the image module (surfgrad/image/image_decode.h): its
// channels as float, NaN and infinities kept (readCorners names the corner
// and channel), at most kMaxFeatureMapSize + 1 pixels per side and the
// 9 channels of a map (at most 604 MB, as a map of the largest size
// holds: no budget beyond these limits, as before).
image::DecodedImage decode(const std::string& bytes, const std::string& name) {
    image::DecodeOptions opt;
    opt.maxSide = kMaxFeatureMapSize + 1;
    opt.maxChannels = int(channelNames().size());
    opt.toFloat = true;
    opt.finiteOnly = false;
    opt.checkMemory = [](const image::DecodePlan&) {};
    return image::decodeImageBytes(bytes, name, opt);
}

} // namespace

void save(const FeatureMaps& m, const std::filesystem::path& path) {
    const int g = m.size + 1;
    const std::vector<std::string> names = channelNames();
    const size_t nch = names.size();
    // Corner (i, j) is sample m.index(i, j): row j = 0 (the bottom) first,
    // the writer's order (the file stores scanline 0 = top, j = N).
    std::vector<float> px(size_t(g) * size_t(g) * nch);
    for (size_t k = 0; k < size_t(g) * size_t(g); ++k) {
        float* p = &px[k * nch];
        p[0] = m.dist[k];
        p[1] = m.gradX[k];
        p[2] = m.gradY[k];
        p[3] = float(m.left[k]);
        p[4] = float(m.seg[k]);
        p[5] = m.hPos[k];
        p[6] = m.vPos[k];
        p[7] = m.hAngle[k];
        p[8] = m.vAngle[k];
    }
    image::WriteOptions options;
    options.type = image::SampleType::Float;
    options.channelNames = names;
    options.attributes = {{"surfgrad:featureMapsVersion", kFeatureMapsVersion},
                          {"surfgrad:mode", toString(m.mode)},
                          {"surfgrad:size", m.size},
                          {"surfgrad:inputToTexelScaleX", m.inputToTexel.scale.x},
                          {"surfgrad:inputToTexelScaleY", m.inputToTexel.scale.y},
                          {"surfgrad:inputToTexelOffsetX", m.inputToTexel.offset.x},
                          {"surfgrad:inputToTexelOffsetY", m.inputToTexel.offset.y},
                          {"surfgrad:bandTexels", m.bandTexels},
                          {"surfgrad:smoothIterations", m.smoothIterations},
                          {"surfgrad:source", m.source},
                          {"surfgrad:layout", kLayout}};
    if (m.hasNearField()) {
        options.attributes.push_back({"surfgrad:nearBandTexels", m.nearBandTexels});
        std::string table;
        for (const std::string& p : m.profiles) table += (table.empty() ? "" : ";") + p;
        if (!table.empty()) options.attributes.push_back({"surfgrad:nearProfiles", table});
        std::vector<float> pieces;
        pieces.reserve(m.pieces.size() * kPieceFloats);
        for (const NearPiece& p : m.pieces) {
            pieces.insert(pieces.end(),
                          {p.p0.x, p.p0.y, p.p1.x, p.p1.y, p.p2.x, p.p2.y, p.curved ? 1.0f : 0.0f,
                           float(p.profile), p.width0, p.width1});
        }
        // (A near field has a piece per input segment: never empty.)
        if (!pieces.empty()) options.attributes.push_back({"surfgrad:nearPieces", pieces});
    }
    image::writeImageFile(path, {px.data(), g, g, int(nch)}, options);
}

FeatureMaps load(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw io::InputError(path.string(), "",
                             std::filesystem::exists(path, ec) ? "not a regular file"
                                                               : "no such file");
    }
    // The largest map (kMaxFeatureMapSize, 9 float channels, uncompressed)
    // is about 600 MB; read into memory so the header is checked first.
    return loadFromMemory(io::readFile(path, size_t(1) << 30), path.string());
}

FeatureMaps loadFromMemory(const std::string& bytes, const std::string& name) {
    // OpenEXR allocates what its header declares before reading it: the
    // header is checked first (surfgrad/image/image_header.h).
    io::scanExrHeader(io::MemoryBytes(bytes), name);
    image::DecodedImage file = decode(bytes, name);
    FeatureMaps m = readMetadata(file, name);
    readCorners(file, name, m);
    std::vector<uint8_t>().swap(file.data); // in m now: free before the configuration checks
    checkConfigurations(name, m);
    readNearField(file, name, m);
    return m;
}

} // namespace sg::features
