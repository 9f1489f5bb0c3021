// OpenEXR storage of feature maps: lossless round trip (the loaded maps
// evaluate bit for bit like the baked ones), atomic writes, and clear errors
// for everything a hostile or damaged file can contain.
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <fstream>

#include "maps_test_util.h"
#include "surfgrad/base/io.h"

using namespace sg::features;
using namespace sgtest;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("sg_features_storage_" + std::to_string(::getpid()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

FeatureMaps sampleMaps(BakeMode mode) {
    NetBuilder b;
    b.circle({8.3, 8.1}, 4.2, 8);
    b.polyline({{1.5, 14.2}, {14.5, 12.9}, {9.0, 2.0}});
    return bake(b.net, texelSpace(16, mode));
}

// Writes `spec` and float pixels to path with OIIO directly (to forge files).
void writeExr(const fs::path& path, OIIO::ImageSpec spec, const std::vector<float>& px) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    ASSERT_TRUE(out->close());
}

std::string loadError(const fs::path& p) {
    try {
        load(p);
    } catch (const sg::io::InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(FeatureMapsStorage, RoundTripIsExact) {
    TempDir dir;
    for (BakeMode mode : {BakeMode::Linear, BakeMode::Quadratic}) {
        FeatureMaps m = sampleMaps(mode);
        m.source = "unit test";
        m.inputToTexel = {{2.5, 2.5}, {-1.25, 3.0}};
        fs::path p = dir.path / "maps.exr";
        save(m, p);
        FeatureMaps l = load(p);
        EXPECT_EQ(l.size, m.size);
        EXPECT_EQ(l.mode, m.mode);
        EXPECT_EQ(l.source, "unit test");
        EXPECT_EQ(l.inputToTexel.scale, m.inputToTexel.scale);
        EXPECT_EQ(l.inputToTexel.offset, m.inputToTexel.offset);
        EXPECT_EQ(l.bandTexels, m.bandTexels);
        EXPECT_EQ(l.smoothIterations, m.smoothIterations);
        EXPECT_EQ(l.dist, m.dist);
        EXPECT_EQ(l.gradX, m.gradX);
        EXPECT_EQ(l.gradY, m.gradY);
        EXPECT_EQ(l.left, m.left);
        EXPECT_EQ(l.seg, m.seg);
        EXPECT_EQ(l.hPos, m.hPos);
        EXPECT_EQ(l.vPos, m.vPos);
        EXPECT_EQ(l.hAngle, m.hAngle);
        EXPECT_EQ(l.vAngle, m.vAngle);
        GpuFeatureMaps a = m.packGpu(), b = l.packGpu();
        EXPECT_EQ(a.cornerPairs, b.cornerPairs);
        EXPECT_EQ(a.edges, b.edges);
        // Same bytes from memory.
        std::string bytes = sg::io::readFile(p);
        FeatureMaps mm = loadFromMemory(bytes, "memory");
        EXPECT_EQ(mm.dist, m.dist);
        EXPECT_EQ(mm.seg, m.seg);
    }
}

TEST(FeatureMapsStorage, WriteIsAtomicAndRefusesDirectories) {
    TempDir dir;
    FeatureMaps m = sampleMaps(BakeMode::Linear);
    EXPECT_THROW(save(m, dir.path), sg::io::InputError);
    EXPECT_THROW(save(m, dir.path / "missing" / "x.exr"), sg::io::InputError);
    save(m, dir.path / "ok.exr");
    for (const auto& e : fs::directory_iterator(dir.path)) {
        EXPECT_EQ(e.path().filename(), "ok.exr") << "leftover temporary file " << e.path();
    }
}

TEST(FeatureMapsStorage, RejectsBadFiles) {
    TempDir dir;
    FeatureMaps m = sampleMaps(BakeMode::Quadratic);
    fs::path good = dir.path / "good.exr";
    save(m, good);
    // Not a file / not an image / not an EXR.
    EXPECT_NE(loadError(dir.path / "none.exr").find("no such file"), std::string::npos);
    sg::io::writeFileAtomically(dir.path / "text.exr", "hello");
    EXPECT_NE(loadError(dir.path / "text.exr"), "");
    // Truncated EXR.
    std::string bytes = sg::io::readFile(good);
    sg::io::writeFileAtomically(dir.path / "trunc.exr", bytes.substr(0, bytes.size() / 2));
    EXPECT_NE(loadError(dir.path / "trunc.exr"), "");
    // Header attributes are checked before OpenEXR allocates them: the
    // first attribute's size word (after magic, version, its name and type,
    // each null-terminated) raised to 2^31 - 1, far past the end of the file.
    {
        const size_t nameEnd = bytes.find('\0', 8), typeEnd = bytes.find('\0', nameEnd + 1);
        ASSERT_NE(typeEnd, std::string::npos);
        const std::string firstAttr = bytes.substr(8, nameEnd - 8);
        const size_t sizeAt = typeEnd + 1;
        std::string forged = bytes;
        const unsigned char big[4] = {0xFF, 0xFF, 0xFF, 0x7F};
        forged.replace(sizeAt, 4, reinterpret_cast<const char*>(big), 4);
        sg::io::writeFileAtomically(dir.path / "hugeattr.exr", forged);
        const std::string e = loadError(dir.path / "hugeattr.exr");
        EXPECT_NE(e.find("attribute '" + firstAttr + "' declares 2147483647 bytes"),
                  std::string::npos)
            << e;
        // A chlist whose records do not end exactly at its declared size:
        // OpenEXR reads channel records up to the empty name whatever the
        // size says, so the two would disagree on where the next attribute
        // starts (a fuzzed 820-byte file then asked for 2 GB).
        const size_t chAt = bytes.find(std::string("channels\0chlist\0", 16));
        ASSERT_NE(chAt, std::string::npos);
        std::string shortList = bytes;
        shortList[chAt + 16] =
            char(static_cast<unsigned char>(shortList[chAt + 16]) - 1); // size - 1 (low byte)
        sg::io::writeFileAtomically(dir.path / "chlist.exr", shortList);
        EXPECT_NE(loadError(dir.path / "chlist.exr").find("type chlist declares"),
                  std::string::npos);
        std::string multi = bytes;
        multi[5] =
            char(static_cast<unsigned char>(multi[5]) | 0x10); // version bit 0x1000: multi-part
        sg::io::writeFileAtomically(dir.path / "multipart.exr", multi);
        EXPECT_NE(loadError(dir.path / "multipart.exr").find("multi-part"), std::string::npos);
    }

    // Forged files: start from the real spec and pixels, break one thing.
    auto in = OIIO::ImageInput::open(good.string());
    ASSERT_TRUE(in);
    OIIO::ImageSpec spec = in->spec();
    std::vector<float> px(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    in.reset();
    auto forge = [&](const std::string& name, auto&& edit) {
        OIIO::ImageSpec s = spec;
        std::vector<float> p = px;
        edit(s, p);
        fs::path f = dir.path / (name + ".exr");
        writeExr(f, s, p);
        return loadError(f);
    };
    auto chan = [&](const char* n) {
        for (int c = 0; c < spec.nchannels; ++c) {
            if (spec.channel_name(c) == n) return c;
        }
        return -1;
    };
    const int nc = spec.nchannels;
    // Metadata.
    EXPECT_NE(
        forge("version", [](auto& s, auto&) { s.attribute("surfgrad:featureMapsVersion", 99); })
            .find("featureMapsVersion"),
        std::string::npos);
    EXPECT_NE(forge("mode", [](auto& s, auto&) { s.attribute("surfgrad:mode", "cubic"); })
                  .find("surfgrad:mode"),
              std::string::npos);
    EXPECT_NE(
        forge("size", [](auto& s, auto&) { s.attribute("surfgrad:size", 15); }).find("pixels"),
        std::string::npos);
    EXPECT_NE(forge("nosize", [](auto& s, auto&) { s.erase_attribute("surfgrad:size"); })
                  .find("surfgrad:size"),
              std::string::npos);
    EXPECT_NE(forge("scale",
                    [](auto& s, auto&) {
                        double z = 0.0;
                        s.attribute("surfgrad:inputToTexelScaleX", OIIO::TypeDesc::DOUBLE, &z);
                    })
                  .find("Scale"),
              std::string::npos);
    EXPECT_NE(forge("band",
                    [](auto& s, auto&) {
                        double b = 1e9;
                        s.attribute("surfgrad:bandTexels", OIIO::TypeDesc::DOUBLE, &b);
                    })
                  .find("band"),
              std::string::npos);
    // Metadata of the wrong type, a data window off the origin.
    EXPECT_NE(forge("floatsize", [](auto& s, auto&) { s.attribute("surfgrad:size", 16.0f); })
                  .find("surfgrad:size: missing or not an integer"),
              std::string::npos);
    EXPECT_NE(forge("origin", [](auto& s, auto&) { s.x = 3; }).find("at origin 0"),
              std::string::npos);
    // Channels.
    EXPECT_NE(forge("chname", [](auto& s, auto&) { s.channelnames[0] = "Z"; }).find("channel d"),
              std::string::npos);
    EXPECT_NE(forge("halfch",
                    [&](auto& s, auto&) {
                        s.channelformats.assign(size_t(s.nchannels), OIIO::TypeDesc::FLOAT);
                        s.channelformats[size_t(chan("gx"))] = OIIO::TypeDesc::HALF;
                    })
                  .find("channel gx: must be 32-bit float"),
              std::string::npos);
    // Values.
    EXPECT_NE(forge("nan", [&](auto&, auto& p) { p[size_t(chan("gx"))] = std::nanf(""); })
                  .find("not finite"),
              std::string::npos);
    EXPECT_NE(
        forge("negd", [&](auto&, auto& p) { p[size_t(chan("d"))] = -1.0f; }).find("channel d"),
        std::string::npos);
    EXPECT_NE(
        forge("longgrad", [&](auto&, auto& p) { p[size_t(chan("gx"))] = 3.0f; }).find("gradient"),
        std::string::npos);
    EXPECT_NE(forge("left", [&](auto&, auto& p) { p[size_t(chan("left"))] = 0.5f; }).find("left"),
              std::string::npos);
    EXPECT_NE(forge("seg", [&](auto&, auto& p) { p[size_t(chan("seg"))] = 3.0f; }).find("seg"),
              std::string::npos);
    EXPECT_NE(forge("segfrac", [&](auto&, auto& p) { p[size_t(chan("seg"))] = 1.5f; }).find("seg"),
              std::string::npos);
    EXPECT_NE(forge("pos", [&](auto&, auto& p) { p[size_t(chan("hT"))] = 0.0f; }).find("hT"),
              std::string::npos);
    EXPECT_NE(
        forge("grid", [&](auto&, auto& p) { p[size_t(chan("hT"))] = 0.5f + 1e-5f; }).find("grid"),
        std::string::npos);
    EXPECT_NE(forge("angle", [&](auto&, auto& p) { p[size_t(chan("hA"))] = 2.0f; }).find("hA"),
              std::string::npos);
    // A segment ending on an edge without a point: find a texel with one
    // and remove its S/N/E/W point.
    EXPECT_NE(forge("segpoint",
                    [&](auto& s, auto& p) {
                        for (size_t k = 0; k < p.size() / size_t(nc); ++k) {
                            float w = p[k * size_t(nc) + size_t(chan("seg"))];
                            if (w == 0.0f) continue;
                            uint32_t word = uint32_t(w);
                            int e = int((word >> 2) & 3u);
                            // Pixel k is corner (i, j) with row = k / g, j = g - 1 - row.
                            int g = s.width;
                            size_t row = k / size_t(g);
                            // S edge: hT of this corner; W edge: vT of this corner;
                            // N edge: hT one row up; E edge: vT one to the right.
                            size_t idx = e == 0 ? k : e == 3 ? k : e == 2 ? k - size_t(g) : k + 1;
                            (void)row;
                            p[idx * size_t(nc) + size_t(chan(e == 0 || e == 2 ? "hT" : "vT"))] =
                                -1.0f;
                            return;
                        }
                    })
                  .find("without a point"),
              std::string::npos);
    // A curved segment with a signature the runtime cannot use: the angles
    // of a curved texel's edges turned by about 50 degrees (staying on the
    // 16-bit grid, so only the signature check can object).
    std::string curvedErr = forge("badcurve", [&](auto& s, auto& p) {
        int g = s.width;
        for (size_t k = 0; k < p.size() / size_t(nc); ++k) {
            uint32_t word = uint32_t(p[k * size_t(nc) + size_t(chan("seg"))]);
            if (!((word & 3u) && ((word >> 6) & 1u))) continue;
            for (size_t idx : {k, k - size_t(g), k + 1}) {
                for (const char* a : {"hA", "vA"}) {
                    float& ang = p[idx * size_t(nc) + size_t(chan(a))];
                    if (ang == 0.0f) continue;
                    // Angle code of u = tan(theta / 2) (layout.glsl), moved by half its range.
                    double code = std::round(std::tan(0.5 * double(ang)) * 32767.0);
                    code = code > 0.0 ? code - 16384.0 : code + 16384.0;
                    ang = float(2.0 * std::atan(code / 32767.0));
                }
            }
            return;
        }
    });
    EXPECT_NE(curvedErr.find("invalid signature"), std::string::npos) << curvedErr;
    // The message format: "<file>: <element>: <reason>".
    EXPECT_NE(
        forge("msg", [&](auto&, auto& p) { p[size_t(chan("d"))] = -1.0f; }).find(".exr: corner ("),
        std::string::npos);
}

// The exact near field round-trips (pieces, profiles, band: the GPU lists
// derived from them are identical), and every forged value is refused.
TEST(FeatureMapsStorage, NearFieldRoundTripAndForgeries) {
    TempDir dir;
    NetBuilder b;
    b.circle({8.3, 8.1}, 4.2, 8);
    b.polyline({{1.5, 14.2}, {14.5, 12.9}, {9.0, 2.0}});
    b.net.curves[0].profile = "seam";
    b.net.curves[1].profile = "table:0,1,0.5";
    b.net.curves[1].width = 2.5;
    b.net.segments.back().width0 = 1.0; // per-vertex widths on the last segment
    b.net.segments.back().width1 = 3.5;
    BakeOptions o = texelSpace(16, BakeMode::Quadratic);
    o.nearField = true;
    FeatureMaps m = bake(b.net, o);
    ASSERT_TRUE(m.hasNearField());
    EXPECT_EQ(m.profiles, (std::vector<std::string>{"seam", "table:0,1,0.5"}));
    EXPECT_EQ(m.nearBandTexels, 3.5 + o.nearMarginTexels); // the widest profile plus the margin
    fs::path good = dir.path / "near.exr";
    save(m, good);
    FeatureMaps l = load(good);
    EXPECT_EQ(l.nearBandTexels, m.nearBandTexels);
    EXPECT_EQ(l.profiles, m.profiles);
    ASSERT_EQ(l.pieces.size(), m.pieces.size());
    for (size_t k = 0; k < m.pieces.size(); ++k) {
        EXPECT_EQ(l.pieces[k].p0, m.pieces[k].p0);
        EXPECT_EQ(l.pieces[k].p1, m.pieces[k].p1);
        EXPECT_EQ(l.pieces[k].p2, m.pieces[k].p2);
        EXPECT_EQ(l.pieces[k].curved, m.pieces[k].curved);
        EXPECT_EQ(l.pieces[k].profile, m.pieces[k].profile);
        EXPECT_EQ(l.pieces[k].width0, m.pieces[k].width0);
        EXPECT_EQ(l.pieces[k].width1, m.pieces[k].width1);
    }
    GpuFeatureMaps a = m.packGpu(), c = l.packGpu();
    EXPECT_EQ(a.nearLists, c.nearLists);
    EXPECT_EQ(a.pieces, c.pieces);

    auto in = OIIO::ImageInput::open(good.string());
    ASSERT_TRUE(in);
    OIIO::ImageSpec spec = in->spec();
    std::vector<float> px(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    in.reset();
    const OIIO::ParamValue* pv = spec.find_attribute("surfgrad:nearPieces");
    ASSERT_TRUE(pv);
    const float* f = static_cast<const float*>(pv->data());
    const std::vector<float> pieces(f, f + pv->type().arraylen);
    auto forge = [&](const std::string& name, auto&& edit) {
        OIIO::ImageSpec s = spec;
        std::vector<float> v = pieces;
        edit(s, v);
        s.attribute("surfgrad:nearPieces", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, int(v.size())),
                    v.data());
        fs::path file = dir.path / (name + ".exr");
        writeExr(file, s, px);
        return loadError(file);
    };
    auto expectError = [](const std::string& e, const char* what) {
        EXPECT_NE(e.find(what), std::string::npos) << e;
    };
    expectError(forge("nan", [](auto&, auto& v) { v[0] = std::nanf(""); }), "not finite");
    expectError(forge("far", [](auto&, auto& v) { v[1] = 3e6f; }), "1e6 texels");
    expectError(forge("flag", [](auto&, auto& v) { v[6] = 0.5f; }), "curved flag");
    expectError(forge("profile", [](auto&, auto& v) { v[7] = 5.0f; }), "profile index");
    expectError(forge("width", [](auto&, auto& v) { v[8] = 1e3f; }), "profile width");
    expectError(forge("count", [](auto&, auto& v) { v.pop_back(); }), "10 values per piece");
    expectError(forge("point", [](auto&, auto& v) { v[4] = v[0], v[5] = v[1]; }),
                "coincident end points");
    expectError(forge("band",
                      [](auto& s, auto&) {
                          double band = 100.0;
                          s.attribute("surfgrad:nearBandTexels", OIIO::TypeDesc::DOUBLE, &band);
                      }),
                "nearBandTexels");
    expectError(forge("table",
                      [](auto& s, auto&) { s.attribute("surfgrad:nearProfiles", "crease;bogus"); }),
                "unknown profile");
    // Without the table (absent: empty), the pieces' profile indices point nowhere.
    expectError(
        forge("notable", [](auto& s, auto&) { s.erase_attribute("surfgrad:nearProfiles"); }),
        "profile index");
    // A line whose middle point is not its midpoint.
    size_t line = 0;
    while (line < pieces.size() / 10 && pieces[line * 10 + 6] != 0.0f) ++line;
    ASSERT_LT(line, pieces.size() / 10);
    expectError(forge("midpoint", [&](auto&, auto& v) { v[line * 10 + 2] += 0.25f; }), "midpoint");
}
