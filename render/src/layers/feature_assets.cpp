// The feature layer kind's own assets (feature_assets.h): loading and
// baking the feature maps, the kind's plan slots, their GL textures and CPU
// samplers (the LayerKindAssets hooks of layer_feature.cpp's entry), and the
// prefiltered slope chain of "antialias": "lean" layers with its producer.
#include "feature_assets.h"

#include <algorithm>
#include <atomic>

#include <epoxy/gl.h>
#include <tbb/parallel_for.h>

#include "surfgrad/gl/context.h"
#include "surfgrad/base/threads.h"

namespace sg::render {

const LayerKind& featureLayerKind(); // layer_feature.cpp

namespace fs = std::filesystem;

std::string FeatureSource::key() const {
    if (!mapsFile.empty()) return "maps:" + mapsFile.lexically_normal().string();
    return "bake:" + curvesKind + ":" + curvesFile.lexically_normal().string() + ":" + text + ":" +
           std::to_string(size) + (quadratic ? ":quadratic:" : ":linear:") +
           std::to_string(marginTexels) +
           (nearField ? ":near:" + std::to_string(nearWidthTexels) : std::string());
}

const FeatureMapsAsset* findFeatureMaps(const SceneAssets& assets, const std::string& key) {
    auto it = assets.kindAssets.find(featureLayerKind().name);
    if (it == assets.kindAssets.end()) return nullptr;
    const auto& maps = static_cast<const FeatureAssets&>(*it->second).maps;
    auto m = maps.find(key);
    return m != maps.end() ? m->second.get() : nullptr;
}

namespace detail {

FeatureChainTextures featureChainTextures(const FeatureMapsAsset& maps,
                                          const FeatureChainSource& src, int samplesPerAxis,
                                          int threads) {
    SG_EXPECTS(samplesPerAxis >= 1 && maps.gpu.size >= 1, "a chain of loaded maps");
    SG_EXPECTS(threads >= 0 && threads <= sg::kMaxThreads,
               "threads is 0 (all cores) .. kMaxThreads");
    namespace G = sg::glsl;
    const sg::features::GpuFeatureMaps& gpu = maps.gpu;
    const int n = gpu.size;
    const bool near = src.nearExact && gpu.hasNearField();
    const G::SgFeatProfile layerProfile =
        sg::features::makeProfile(src.profile, src.depth, src.w0, src.width);
    // Where every profile has ended (d >= w gives the flat base's slope 0):
    // texels whose centre is farther than that plus half a diagonal and a
    // margin for the interpolated distance hold zero moments.
    const float reach =
        (near ? std::max(float(maps.nearBandTexels), layerProfile.w) : layerProfile.w) + 1.5f;
    const auto nm = near ? sg::features::NearMode::Exact : sg::features::NearMode::Paper;
    auto slopeAt = [&](glm::vec2 pos) {
        G::SgFeatResult r = sg::features::sample(gpu, pos, nm);
        G::SgFeatProfile pr =
            near ? G::sgFeatCurveProfile(gpu.pieceSampler(), layerProfile, r) : layerProfile;
        return G::sgFeatAaSlope(r, pr, src.paperMode);
    };
    std::vector<glm::vec4> texelsA(size_t(n) * size_t(n), glm::vec4(0.0f));
    std::vector<glm::vec4> texelsB(size_t(n) * size_t(n), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    const double inv = 1.0 / double(samplesPerAxis);
    const double norm = 1.0 / (double(samplesPerAxis) * double(samplesPerAxis));
    auto row = [&](int j) {
        for (int i = 0; i < n; ++i) {
            const size_t at = size_t(j) * size_t(n) + size_t(i);
            if (sg::features::sample(gpu, glm::vec2(i + 0.5f, j + 0.5f), nm).dist > reach)
                continue; // zero moments (texB's w is 1 everywhere)
            // Midpoint rule over the texel square, summed in double.
            glm::dvec4 sumA(0.0), sumB(0.0);
            for (int b = 0; b < samplesPerAxis; ++b)
                for (int a = 0; a < samplesPerAxis; ++a) {
                    glm::vec2 pos(float(i + (a + 0.5) * inv), float(j + (b + 0.5) * inv));
                    glm::vec4 ta, tb;
                    G::sgFeatAaMomentTexel(slopeAt(pos), ta, tb);
                    sumA += glm::dvec4(ta);
                    sumB += glm::dvec4(tb);
                }
            texelsA[at] = glm::vec4(sumA * norm);
            texelsB[at] = glm::vec4(sumB * norm);
        }
    };
    // Rows write disjoint texels: any schedule gives the same bits.
    if (threads == 1 || n < kFeatureChainSerialBelowSize) {
        for (int j = 0; j < n; ++j) row(j);
    } else {
        sg::runWithThreads(threads, [&] { tbb::parallel_for(0, n, row); });
    }
    return {makeTexture(n, n, std::move(texelsA), Wrap::Clamp),
            makeTexture(n, n, std::move(texelsB), Wrap::Clamp)};
}

} // namespace detail

namespace {

using P = FeatureParams;

// ---------------------------------------------------------------------------
// Loading

// Loads or bakes a feature layer's maps (features are not baked unless an
// enabled layer uses them).
std::shared_ptr<const FeatureMapsAsset> loadFeatureMaps(const FeatureSource& f,
                                                        const std::string& sceneName) {
    namespace sf = sg::features;
    static std::atomic<uint64_t> nextUid{1};
    sf::FeatureMaps maps;
    if (!f.mapsFile.empty()) {
        maps = detail::fromReferencedFile(sceneName, f.fieldPath, [&] {
            std::error_code ec;
            if (!fs::is_regular_file(f.mapsFile, ec)) {
                throw io::InputError(f.mapsFile.string(), "",
                                     fs::exists(f.mapsFile, ec) ? "not a regular file"
                                                                : "does not exist");
            }
            return sf::load(f.mapsFile);
        });
    } else {
        sf::CurveNetwork net =
            detail::fromReferencedFile(sceneName, f.fieldPath + "." + f.curvesKind, [&] {
                return f.curvesKind == "svg"    ? sf::loadSvg(f.curvesFile)
                       : f.curvesKind == "json" ? sf::loadCurvesJson(f.curvesFile)
                                                : sf::loadFont(f.curvesFile, f.text);
            });
        sf::BakeOptions opt;
        opt.size = f.size;
        opt.mode = f.quadratic ? sf::BakeMode::Quadratic : sf::BakeMode::Linear;
        opt.marginTexels = f.marginTexels;
        opt.nearField = f.nearField;
        opt.nearWidthTexels = f.nearWidthTexels;
        maps = sf::bake(net, opt);
    }
    auto a = std::make_shared<FeatureMapsAsset>();
    a->gpu = maps.packGpu();
    a->bandTexels = maps.bandTexels;
    a->quadratic = maps.mode == sf::BakeMode::Quadratic;
    a->nearBandTexels = maps.nearBandTexels;
    a->uid = nextUid++;
    return a;
}

// The profile must fit the band where the maps' distances are exact, and,
// with "near": "exact", the maps' near field must cover it.
void checkLayer(const Layer& L, const FeatureMapsAsset& maps, const std::string& sceneName) {
    const P& p = L.params<P>();
    const double band = maps.bandTexels;
    if (double(p.width) > band - 1.5) {
        throw io::InputError(sceneName, L.fieldPath + ".width",
                             "the profile width must be at most " + std::to_string(band - 1.5) +
                                 " texels (the maps hold exact distances up to " +
                                 std::to_string(band) + ")");
    }
    const double nearBand = maps.nearBandTexels;
    if (p.nearExact && nearBand <= 0.0) {
        throw io::InputError(sceneName, L.fieldPath + ".near",
                             "\"exact\" needs maps baked with the near field (surfgrad "
                             "features bake --near exact)");
    }
    if (p.nearExact && double(p.width) > nearBand) {
        throw io::InputError(sceneName, L.fieldPath + ".width",
                             "the profile width must be at most the near field's band " +
                                 std::to_string(nearBand) +
                                 " texels (bake with a larger --near-width)");
    }
}

// LayerKindAssets::load: the maps `layers` read that are not loaded yet
// (stored in a new FeatureAssets, so copies of the assets keep theirs),
// each layer checked against its maps as it comes.
void load(const Scene& scene, const std::vector<const Layer*>& layers, SceneAssets& assets) {
    for (const Layer* L : layers) {
        const FeatureSource& src = *L->params<P>().source;
        const std::string key = src.key();
        const FeatureMapsAsset* maps = findFeatureMaps(assets, key);
        if (!maps) {
            auto next = std::make_shared<FeatureAssets>();
            auto& slot = assets.kindAssets[featureLayerKind().name];
            if (slot) next->maps = static_cast<const FeatureAssets&>(*slot).maps;
            auto loaded = loadFeatureMaps(src, scene.sourceName);
            maps = loaded.get();
            next->maps[key] = std::move(loaded);
            slot = std::move(next);
            assets.log.push_back("feature maps " + key + ": " + std::to_string(maps->gpu.size) +
                                 "^2 texels");
        }
        checkLayer(*L, *maps, scene.sourceName);
    }
}

// ---------------------------------------------------------------------------
// The prefiltered chain as a texture producer

class ChainProducer final : public TextureProducer {
public:
    explicit ChainProducer(FeatureChainSource c) : c_(std::move(c)) {}
    std::string key() const override {
        return "featchain:" + c_.mapsKey + ":" + c_.profile + ":" + std::to_string(c_.depth) + ":" +
               std::to_string(c_.w0) + ":" + std::to_string(c_.width) +
               (c_.paperMode ? ":paper" : ":surfgrad") + (c_.nearExact ? ":exact" : ":interp") +
               ":part" + std::to_string(c_.part);
    }
    // Both parts in one pass from the loaded maps; the part not asked for
    // is stored under its own key.
    std::shared_ptr<const TextureImage> make(const Scene& scene, SceneAssets& assets,
                                             const TextureSource& src,
                                             const TextureLoadOptions& opt) const override {
        const FeatureMapsAsset* fm = findFeatureMaps(assets, c_.mapsKey);
        SG_ASSERT(fm, "feature maps load before their chains");
        const int n = fm->gpu.size;
        try {
            detail::checkTextureBudget("prefiltered chain of feature maps " + c_.mapsKey, opt,
                                       std::to_string(n) + "x" + std::to_string(n) +
                                           " texels, 2 x 4 channels as float",
                                       2 * textureBytes(n, n, 4, TexelType::Float), 0);
        } catch (const io::InputError& e) {
            throw io::InputError(scene.sourceName, src.fieldPath, e.what());
        }
        detail::FeatureChainTextures chain = detail::featureChainTextures(*fm, c_);
        FeatureChainSource other = c_;
        other.part = 1 - c_.part;
        assets.textures[ChainProducer(other).key()] =
            std::make_shared<const TextureImage>(std::move(chain.part[other.part]));
        return std::make_shared<const TextureImage>(std::move(chain.part[c_.part]));
    }

private:
    FeatureChainSource c_;
};

// ---------------------------------------------------------------------------
// Plan

struct FeatureFlags { // KindPlan::data
    bool curved = false, near = false, lean = false;
};

// LayerKindAssets::plan: the layer's maps get a slot (one per distinct
// maps key); the program's options follow the maps and the layer.
void plan(const Layer& L, const SceneAssets& assets, KindPlan& kp, PlanLayer& pl) {
    const FeatureSource& src = *L.params<P>().source;
    const std::string key = src.key();
    auto it = std::find(kp.keys.begin(), kp.keys.end(), key);
    pl.kindSlot = int(it - kp.keys.begin());
    if (it == kp.keys.end()) kp.keys.push_back(key);
    pl.kindIndex = kp.layerCount++;
    if (!kp.data.has_value()) kp.data = FeatureFlags{};
    FeatureFlags& f = std::any_cast<FeatureFlags&>(kp.data);
    // Effects on demand inside the evaluator: the curved-segment code
    // (TOG 2008) only when some map was baked with curves.
    const FeatureMapsAsset* fm = findFeatureMaps(assets, key);
    if (fm && fm->quadratic) f.curved = true;
    // ... and the exact near field only when a layer uses one.
    if (fm && src.nearField && fm->nearBandTexels > 0.0) f.near = true;
    // ... and the prefiltered chain only when a layer antialiases.
    if (L.params<P>().lean) f.lean = true;
}

// ---------------------------------------------------------------------------
// GL: the maps' textures by FeatureMapsAsset::uid, per renderer: corner
// pairs, edges and, for maps with an exact near field, its lists and
// pieces (else 0); all RGBA32UI, read with texelFetch only.

struct GlTextures {
    std::map<uint64_t, std::array<GLuint, 4>> byUid;
    GlTextures() = default;
    GlTextures(const GlTextures&) = delete;
    GlTextures& operator=(const GlTextures&) = delete;
    ~GlTextures() {
        for (auto& [uid, t] : byUid)
            for (GLuint x : t)
                if (x) glDeleteTextures(1, &x);
    }
    const std::array<GLuint, 4>& of(const FeatureMapsAsset& fm) {
        auto it = byUid.find(fm.uid);
        if (it != byUid.end()) return it->second;
        const auto& g = fm.gpu;
        std::array<GLuint, 4> t{0, 0, 0, 0};
        auto upload = [](GLuint& x, int w, int h, const std::vector<uint32_t>& data) {
            glCreateTextures(GL_TEXTURE_2D, 1, &x);
            glTextureStorage2D(x, 1, GL_RGBA32UI, w, h);
            glTextureSubImage2D(x, 0, 0, 0, w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT, data.data());
            glTextureParameteri(x, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(x, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        };
        upload(t[0], g.cornerPairsWidth(), g.cornerPairsHeight(), g.cornerPairs);
        upload(t[1], g.size, g.size, g.edges);
        if (g.hasNearField()) {
            upload(t[2], g.size, g.nearHeight, g.nearLists);
            upload(t[3], SG_FEAT_PIECES_WIDTH, g.piecesHeight, g.pieces);
        }
        sg::gl::checkError("feature map upload");
        return byUid.emplace(fm.uid, t).first->second;
    }
};

int gpuUnits(const KindPlan& kp) {
    const bool near = kp.data.has_value() && std::any_cast<const FeatureFlags&>(kp.data).near;
    return (near ? 4 : 2) * int(kp.keys.size());
}

// LayerKindAssets::bindGpu: each slot's maps on 2 (4 with the near field)
// units from c.firstUnit; the per-layer sampler arrays point at them (and
// at the base map or the chain, regular textures).
void bindGpu(const KindGpuContext& c) {
    if (!c.cache) c.cache = std::make_shared<GlTextures>();
    GlTextures& tex = *static_cast<GlTextures*>(c.cache.get());
    const FeaturePlan fp = featurePlan(c.plan);
    const int unitsPerMap = fp.near ? 4 : 2;
    for (size_t f = 0; f < c.kindPlan.keys.size(); ++f) {
        const FeatureMapsAsset* fm = findFeatureMaps(c.assets, c.kindPlan.keys[f]);
        std::array<GLuint, 4> t{0, 0, 0, 0};
        if (fm) t = tex.of(*fm);
        if (!c.uniform) continue; // upload only
        // Maps without a near field: their corner texture stands in for the
        // near textures, which such layers never read (an integer sampler
        // needs an integer texture bound).
        if (!t[2]) t[2] = t[3] = t[0];
        const GLuint unit = GLuint(c.firstUnit + unitsPerMap * int(f));
        for (int k = 0; k < unitsPerMap; ++k) glBindTextureUnit(unit + GLuint(k), t[size_t(k)]);
    }
    if (!c.uniform) return;
    for (const auto& g : c.plan.groups)
        for (const auto& pl : g) {
            if (pl.kindIndex < 0 || pl.layer->kind != c.kindPlan.kind) continue;
            std::string idx = "[" + std::to_string(pl.kindIndex) + "]";
            GLint unit = GLint(c.firstUnit + unitsPerMap * pl.kindSlot);
            glUniform1i(c.uniform(("uFeatCorners" + idx).c_str()), unit);
            glUniform1i(c.uniform(("uFeatEdges" + idx).c_str()), unit + 1);
            if (fp.near) {
                glUniform1i(c.uniform(("uFeatNear" + idx).c_str()), unit + 2);
                glUniform1i(c.uniform(("uFeatPieces" + idx).c_str()), unit + 3);
            }
            glUniform1i(c.uniform(("uFeatBase" + idx).c_str()), GLint(pl.tex[0]));
            if (fp.lean) { // layers without the chain never read it
                glUniform1i(c.uniform(("uFeatChainA" + idx).c_str()), GLint(pl.tex[0]));
                glUniform1i(c.uniform(("uFeatChainB" + idx).c_str()),
                            GLint(pl.tex[1] >= 0 ? pl.tex[1] : pl.tex[0]));
            }
        }
}

// ---------------------------------------------------------------------------
// CPU: the samplers of each slot's maps (none for maps not loaded).

std::any cpuData(const KindPlan& kp, const SceneAssets& assets) {
    std::vector<detail::FeatureSamplers> s(kp.keys.size());
    for (size_t i = 0; i < s.size(); ++i) {
        const FeatureMapsAsset* fm = findFeatureMaps(assets, kp.keys[i]);
        if (!fm) continue;
        s[i].corners = fm->gpu.cornerSampler();
        s[i].edges = fm->gpu.edgeSampler();
        if (fm->gpu.hasNearField()) {
            s[i].nearLists = fm->gpu.nearSampler();
            s[i].pieces = fm->gpu.pieceSampler();
        }
    }
    return s;
}

} // namespace

std::shared_ptr<const TextureProducer> featureChainProducer(const FeatureChainSource& chain) {
    return std::make_shared<const ChainProducer>(chain);
}

FeaturePlan featurePlan(const MaterialPlan& plan) {
    FeaturePlan fp;
    const KindPlan* kp = findKindPlan(plan, featureLayerKind());
    if (!kp) return fp;
    fp.layerCount = kp->layerCount;
    if (kp->data.has_value()) {
        const auto& f = std::any_cast<const FeatureFlags&>(kp->data);
        fp.curved = f.curved;
        fp.near = f.near;
        fp.lean = f.lean;
    }
    return fp;
}

const LayerKindAssets& featureKindAssets() {
    static const LayerKindAssets hooks{
        .reads = [](const Layer& L) { return L.params<P>().source.has_value(); },
        .load = load,
        .plan = plan,
        .slotCode = 'f',
        .gpuUnits = gpuUnits,
        .bindGpu = bindGpu,
        .cpuData = cpuData,
    };
    return hooks;
}

} // namespace sg::render
