// Layer kind `feature`: feature-curve maps (creases, grooves, seams that
// stay sharp at any magnification; Parilov, Rosenberg, Zorin TR2005-872 and
// Parilov, Zorin TOG 2008) as a TBN-style layer (layer_feature.glsl).
// Batched: the feature layers of a group run in one loop, so the large
// evaluator (shaders/sg/features/) is compiled once however many there are.
// The kind's own assets (the feature maps, their GL textures and CPU
// samplers, the prefiltered chain): feature_assets.{h,cpp}.
#include <algorithm>

#include "feature_assets.h"
#include "layer_emit.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = FeatureParams;
using detail::kHuge;
using detail::SceneNode;
using detail::SceneReader;

// ---------------------------------------------------------------------------
// Scene fields

// "maps" (a file from `surfgrad features bake`) or "curves" (baked when the
// scene loads): the layer's FeatureSource.
void parseSource(const SceneNode& n, const char*, Layer& L, const SceneReader& reader) {
    if (n.has("maps") == n.has("curves")) {
        n.fail("expected exactly one of \"maps\" (feature maps from `surfgrad features bake`) or "
               "\"curves\" (baked when the scene loads)");
    }
    FeatureSource fsrc;
    fsrc.fieldPath = n.sub(n.has("maps") ? "maps" : "curves");
    if (n.has("maps")) {
        fsrc.mapsFile = reader.resolvePath(n.child("maps"), n.string("maps", ""));
    } else {
        SceneNode c = n.child("curves");
        c.allowOnly({"svg", "json", "font", "text", "size", "mode", "margin"});
        int kinds = int(c.has("svg")) + int(c.has("json")) + int(c.has("font"));
        if (kinds != 1) c.fail("expected exactly one of \"svg\", \"json\" or \"font\"");
        fsrc.curvesKind = c.has("svg") ? "svg" : c.has("json") ? "json" : "font";
        fsrc.curvesFile = reader.resolvePath(c.child(fsrc.curvesKind.c_str()),
                                             c.string(fsrc.curvesKind.c_str(), ""));
        if (fsrc.curvesKind == "font") {
            fsrc.text = c.string("text", "");
            if (fsrc.text.empty())
                c.failField("text", "expected the characters to lay out (a non-empty string)");
        } else if (c.has("text")) {
            c.failField("text", "applies to fonts only");
        }
        fsrc.size = c.integer("size", 256, 8, 4096);
        fsrc.quadratic = c.choice("mode", 0, {"linear", "quadratic"}) == 1;
        fsrc.marginTexels = c.number("margin", 8.0, 0.0, 1024.0);
    }
    L.params<P>().source = fsrc;
}

void parseOffset(const SceneNode& n, const char* key, Layer& L, const SceneReader&) {
    if (!n.has(key)) return;
    std::vector<float> o = n.floats(key, -kHuge, kHuge, 2);
    if (o.size() != 2) n.failField(key, "expected [s, t]");
    L.params<P>().offset = glm::vec2(o[0], o[1]);
}

// "near": "paper" (default) or "exact" (docs/features.md): curves are then
// baked with the exact near field, its band covering the layer's width; a
// maps file must have one (checkAssets). Read last (after "width").
void parseNear(const SceneNode& n, const char* key, Layer& L, const SceneReader&) {
    P& p = L.params<P>();
    p.nearExact = n.choice(key, 0, {"paper", "exact"}) == 1;
    if (p.nearExact && p.source) {
        p.source->nearField = true;
        p.source->nearWidthTexels = p.width;
    }
}

void checkProfile(const SceneNode& n, const Layer& L) {
    const P& p = L.params<P>();
    try {
        (void)sg::features::makeProfile(p.profile, p.depth, p.w0, p.width);
    } catch (const io::InputError& e) {
        n.failField("profile", e.reason());
    }
}

// ---------------------------------------------------------------------------
// Records

// sgUnpackFeatureLayer(r0, r1, r2), layer_feature.glsl:
//   r0 = (strength, paperMode, map size N (texels), tiling);
//   r1 = (offset.xy, hasBase, base encoding); r2 = (base flipV, nearExact, 0, 0).
// The map size comes from the assets (0 when packed without them).
RecordLayout layerRecords() {
    using S = G::SgFeatureLayerParams;
    return Records<S, 3>("SgFeatureLayerParams", "sgUnpackFeatureLayer", G::sgUnpackFeatureLayer)
        .field("strength", &S::strength, "r0.x",
               [](const PackInput& in) { return in.layer.strength; })
        .field("paperMode", &S::paperMode, "r0.y",
               [](const PackInput& in) { return in.params<P>().paperMode; })
        .field("mapSize", &S::mapSize, "r0.z",
               [](const PackInput& in) {
                   const auto& src = in.params<P>().source;
                   if (!in.assets || !src) return 0.0f;
                   const FeatureMapsAsset* fm = findFeatureMaps(*in.assets, src->key());
                   return fm ? float(fm->gpu.size) : 0.0f;
               })
        .field("tiling", &S::tiling, "r0.w",
               [](const PackInput& in) { return in.params<P>().tiling; })
        .field("offset", &S::offset, "r1.xy",
               [](const PackInput& in) { return in.params<P>().offset; })
        .field("hasBase", &S::hasBase, "r1.z",
               [](const PackInput& in) { return !in.layer.maps.empty() && !in.params<P>().lean; })
        .field("baseEncoding", &S::baseEncoding, "r1.w",
               [](const PackInput& in) { return int(in.params<P>().encoding); })
        .field("baseFlipV", &S::baseFlipV, "r2.x",
               [](const PackInput& in) { return in.params<P>().flipV; })
        .field("nearExact", &S::nearExact, "r2.y",
               [](const PackInput& in) { return in.params<P>().nearExact; })
        .done();
}

// sgUnpackFeatureAa(r2), layer_feature_aa.glsl: r2.z = lean (the slot
// sgUnpackFeatureLayer leaves 0, so records of layers without it are
// unchanged).
RecordLayout aaRecords() {
    using S = G::SgFeatureAaParams;
    RecordLayout l =
        Records<S, 1>("SgFeatureAaParams", "sgUnpackFeatureAa", G::sgUnpackFeatureAa, 2)
            .field("lean", &S::lean, "r0.z",
                   [](const PackInput& in) { return in.params<P>().lean; })
            .done();
    l.glslFile = "sg/render/layer_feature_aa.glsl";
    return l;
}

// sgUnpackFeatProfile(p0, p1, t0..t3), layer_feature.glsl, records 3..8 of
// the layer: p0 = (kind SG_FEAT_PROFILE_*, depth, w0, w) in texels,
// p1 = (table count, 0, 0, 0), t0..t3 = the 16 table heights.
RecordLayout profileRecords() {
    using S = G::SgFeatProfile;
    auto pr = [](const PackInput& in) -> const S& { return std::any_cast<const S&>(in.prepared); };
    Records<S, 6> r("SgFeatProfile", "sgUnpackFeatProfile", G::sgUnpackFeatProfile, 3);
    r.prepare([](const Layer& L) {
         const P& p = L.params<P>();
         return std::any(sg::features::makeProfile(p.profile, p.depth, p.w0, p.width));
     })
        .field("kind", &S::kind, "r0.x", [pr](const PackInput& in) { return pr(in).kind; })
        .field("depth", &S::depth, "r0.y", [pr](const PackInput& in) { return pr(in).depth; })
        .field("w0", &S::w0, "r0.z", [pr](const PackInput& in) { return pr(in).w0; })
        .field("w", &S::w, "r0.w", [pr](const PackInput& in) { return pr(in).w; })
        .field("tableCount", &S::tableCount, "r1.x",
               [pr](const PackInput& in) { return pr(in).tableCount; });
    for (int i = 0; i < 16; ++i) {
        std::string name = "table[" + std::to_string(i) + "]";
        std::string slot = "r" + std::to_string(2 + i / 4) + "." + "xyzw"[i % 4];
        r.element(name.c_str(), &S::table, size_t(i), slot.c_str(),
                  [pr, i](const PackInput& in) { return pr(in).table[i]; });
    }
    return r.done();
}

// ---------------------------------------------------------------------------
// Emission: one loop per group over the group's feature layers; per-layer
// data come from constant arrays indexed by the (dynamically uniform) loop
// counter. llvmpipe's compile time grows faster than linearly with program
// size (two inlined copies of the evaluator took 40x the time of one).

std::string declarations(const MaterialPlan& plan) {
    const FeaturePlan fp = featurePlan(plan);
    std::vector<int> rec(size_t(fp.layerCount)), uvs(rec.size()), flags(rec.size());
    for (const auto& g : plan.groups)
        for (const auto& pl : g) {
            if (pl.kindIndex < 0 || !pl.layer->is("feature")) continue;
            rec[size_t(pl.kindIndex)] = pl.record;
            uvs[size_t(pl.kindIndex)] = pl.layer->uvSet;
            flags[size_t(pl.kindIndex)] = pl.uberIndex;
        }
    std::string o;
    auto arr = [&](const char* name, const std::vector<int>& v) {
        o += "const int " + std::string(name) + "[" + std::to_string(v.size()) + "] = int[" +
             std::to_string(v.size()) + "](";
        for (size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + std::to_string(v[i]);
        o += ");\n";
    };
    const std::string n = std::to_string(fp.layerCount);
    o += "uniform usampler2D uFeatCorners[" + n + "];\n" + "uniform usampler2D uFeatEdges[" + n +
         "];\n" + "uniform sampler2D uFeatBase[" + n + "];\n";
    if (fp.lean) {
        o += "uniform sampler2D uFeatChainA[" + n + "]; // prefiltered chain: E[d], E[d^2]\n" +
             "uniform sampler2D uFeatChainB[" + n + "]; // prefiltered chain: E[d.x d.y]\n";
    }
    if (fp.near) {
        o += "uniform usampler2D uFeatNear[" + n + "];   // exact near field: lists\n" +
             "uniform usampler2D uFeatPieces[" + n + "]; // exact near field: pieces\n";
    }
    arr("kFeatRecord", rec);
    arr("kFeatUvSet", uvs);
    if (plan.uber) arr("kFeatFlag", flags);
    return o;
}

// The maps a feature layer reads, as the binder's values: in the GLSL
// loop the per-layer sampler arrays indexed by `fi`; on the CPU the
// layer's slot of the plan's feature samplers (LayerKindAssets::cpuData)
// and its textures. Without maps (not loaded) the CPU adds nothing.
struct FeatureMapsGlsl {
    bool loaded = true;
    GlslExpr corners{"uFeatCorners[fi]"}, edges{"uFeatEdges[fi]"}, nearLists{"uFeatNear[fi]"},
        pieces{"uFeatPieces[fi]"}, base{"uFeatBase[fi]"}, chainA{"uFeatChainA[fi]"},
        chainB{"uFeatChainB[fi]"};
};
FeatureMapsGlsl featureMaps(const GlslBinder&) {
    return {};
}

struct FeatureMapsCpu {
    bool loaded = false;
    G::SgFeatCornerSampler corners{};
    G::SgFeatEdgeSampler edges{};
    G::SgFeatNearSampler nearLists{};
    G::SgFeatPieceSampler pieces{};
    G::sampler2D base{}, chainA{}, chainB{};
};
FeatureMapsCpu featureMaps(const CpuBinder& b) {
    const CpuLayerContext& c = b.context();
    const auto* slots = std::any_cast<std::vector<detail::FeatureSamplers>>(c.kindData);
    FeatureMapsCpu m;
    if (c.pl.kindSlot < 0 || !slots || !(*slots)[size_t(c.pl.kindSlot)].corners.rgba) return m;
    const detail::FeatureSamplers& fs = (*slots)[size_t(c.pl.kindSlot)];
    m.loaded = true;
    m.corners = fs.corners;
    m.edges = fs.edges;
    m.nearLists = fs.nearLists;
    m.pieces = fs.pieces;
    // As the GL binding (feature_assets.cpp): base and chain A are slot 0,
    // chain B slot 1 when the layer has the chain; layers without the near
    // field or the chain never read those.
    m.base = m.chainA = c.tex(0);
    m.chainB = c.pl.tex[1] >= 0 ? c.tex(1) : c.tex(0);
    return m;
}

// sgLayerFeature(uv, layer params, profile, corners, edges, base map); the
// exact near field (sgLayerFeatureNear: its lists and pieces) and the
// antialiased chain (sgLayerFeatureAa, layer_feature_aa.glsl: its params,
// chain textures and slopeCov) are variants of their own, chosen per plan
// (FeaturePlan: the loop runs one call for all the group's feature layers;
// a layer without the near field or the chain reads neither, by its
// record's flags).
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    const FeaturePlan fp = featurePlan(b.plan());
    const auto m = featureMaps(b);
    if (!m.loaded) return;
    if (fp.lean && fp.near) {
        return b.addSurfgrad(SG_LAYER_CALL(
            b, sgLayerFeatureNearAa, b.uv(), b.record(0), b.record(2), b.record(1), m.corners,
            m.edges, m.nearLists, m.pieces, m.base, m.chainA, m.chainB, b.slopeCov()));
    }
    if (fp.lean) {
        return b.addSurfgrad(SG_LAYER_CALL(b, sgLayerFeatureAa, b.uv(), b.record(0), b.record(2),
                                           b.record(1), m.corners, m.edges, m.base, m.chainA,
                                           m.chainB, b.slopeCov()));
    }
    if (fp.near) {
        return b.addSurfgrad(SG_LAYER_CALL(b, sgLayerFeatureNear, b.uv(), b.record(0), b.record(1),
                                           m.corners, m.edges, m.nearLists, m.pieces, m.base));
    }
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerFeature, b.uv(), b.record(0), b.record(1), m.corners,
                                m.edges, m.base));
});

// The statements of one feature layer `fi` (a loop index, or a constant
// in the unrolled form), at `indent`: its UV frame `fuv`, its first record
// `r`, and the emitter's statement over them.
std::string featureLayerBody(const MaterialPlan& plan, const PlanLayer& any, uint32_t uvMask,
                             const std::string& in) {
    std::string o = in + "int r = kFeatRecord[fi];\n";
    bool firstUv = true;
    for (int k = 0; k < plan.uvCount; ++k) {
        if (!(uvMask >> k & 1u)) continue;
        const std::string uv = "uv" + std::to_string(k);
        if (firstUv) {
            o += in + "SgUvFrame fuv = " + uv + ";\n";
            firstUv = false;
        } else {
            o += in + "if (kFeatUvSet[fi] == " + std::to_string(k) + ") fuv = " + uv + ";\n";
        }
    }
    return o + in + kEmit.glsl(GlslLayerContext{plan, any, in, true});
}

// One loop over the group's feature layers, so the evaluator is compiled
// once. GLSL 3.30 and ES 3.00 index sampler arrays with constant
// expressions only: there (SG_GLSL_LEGACY) the layers are unrolled, one
// block per layer with `fi` a constant.
std::string groupLoop(const MaterialPlan& plan, const std::vector<const PlanLayer*>& layers,
                      const std::string& indent) {
    const int first = layers.front()->kindIndex, count = int(layers.size());
    uint32_t uvMask = 0;
    for (const PlanLayer* pl : layers) uvMask |= 1u << pl->layer->uvSet;
    // The uber program (bench) switches each layer by a uniform flag.
    const std::string on = "if (uLayerOn[kFeatFlag[fi]] > 0.5) {\n";
    const std::string in = indent + (plan.uber ? "        " : "    ");
    const std::string body = (plan.uber ? indent + "    " + on : "") +
                             featureLayerBody(plan, *layers.front(), uvMask, in) +
                             (plan.uber ? indent + "    }\n" : "");
    std::string o = indent + "// feature layers " + std::to_string(first) + ".." +
                    std::to_string(first + count - 1) +
                    " (one loop: the evaluator is compiled once)\n#ifdef SG_GLSL_LEGACY\n";
    for (int fi = first; fi < first + count; ++fi)
        o += indent + "{\n" + indent + "    const int fi = " + std::to_string(fi) + ";\n" + body +
             indent + "}\n";
    o += "#else\n" + indent + "for (int fi = " + std::to_string(first) + "; fi < " +
         std::to_string(first + count) + "; ++fi) {\n" + body + indent + "}\n#endif\n";
    return o;
}

const LayerBatch kBatch{groupLoop};

// "antialias": "none" (default) or "lean": the layer's maps become the two
// textures of its prefiltered chain (read last: after the source, the
// profile fields, "mode" and "near").
void parseAntialias(const SceneNode& n, const char* key, Layer& L, const SceneReader&) {
    if (!n.has(key)) return;
    P& p = L.params<P>();
    p.lean = n.choice(key, 0, {"none", "lean"}) == 1;
    if (!p.lean) return;
    if (!L.maps.empty())
        n.failField(key, "\"lean\" does not combine with \"base_map\" (the chain holds the "
                         "features' slopes on a flat base): expected \"none\" or no base map");
    if (!p.source) return; // the source's own message
    TextureSource chain;
    chain.fieldPath = n.sub(key);
    chain.wrap = Wrap::Clamp;
    FeatureChainSource c;
    c.mapsKey = p.source->key();
    c.profile = p.profile;
    c.depth = p.depth;
    c.w0 = p.w0;
    c.width = p.width;
    c.paperMode = p.paperMode;
    c.nearExact = p.nearExact;
    for (int part = 0; part < 2; ++part) {
        c.part = part;
        chain.producer = featureChainProducer(c);
        L.maps.push_back(chain);
    }
}

uint32_t mapChannels(const Layer& L, const char*& why) {
    why = "the normal encoding";
    return normalXyChannels(L.params<FeatureParams>().encoding);
}

} // namespace

const LayerKind& featureLayerKind() {
    static const LayerKind kind{
        .name = "feature",
        .sigCode = "fea",
        .doc = "feature-curve maps (Parilov-Zorin 2008) as a TBN-style gradient",
        .example = R"("curves": {"svg": "data:svg/flame.svg", "size": 32})",
        .params =
            {
                param::custom("maps", parseSource,
                              "feature maps (EXR from `surfgrad features bake`)"),
                param::custom("curves", nullptr, "curves baked when the scene loads"),
                param::uvSet(),
                param::number("tiling", &P::tiling, {0.0, kHuge, true}, "map repeats per st unit"),
                param::custom("offset", parseOffset, "[s, t] added after tiling"),
                param::string("profile", &P::profile, "the profile h(d): vgroove, crease, ..."),
                param::number("depth", &P::depth, {-1024.0, 1024.0}, "profile depth, texels"),
                param::number("width", &P::width, {0.0, 1024.0, true},
                              "profile half-width, texels"),
                param::checked(param::number("w0", &P::w0, {0.0, 1024.0},
                                             "band where only the profile acts, texels"),
                               [](const SceneNode& n, const char* key, const Layer& L) {
                                   if (!(L.params<P>().w0 < L.params<P>().width))
                                       n.failField(key, "expected a number < width");
                               }),
                param::choice("mode", &P::paperMode, {{"surfgrad", false}, {"paper", true}},
                              "slopes blend (surfgrad) or the papers' Eq. 1"),
                param::strength(),
                param::optionalMap("base_map", Wrap::Repeat, "normal map under the features"),
                param::encoding(&P::encoding, true),
                param::green(&P::flipV),
                param::custom("near", parseNear,
                              "\"exact\": the maps' exact near field, per-curve profiles"),
                param::custom("antialias", parseAntialias,
                              "\"none\" (default) or \"lean\": exact below a texel, the "
                              "prefiltered slope chain above (widens the lobe)"),
            },
        .makeParams = [] { return std::any(P{}); },
        .check = checkProfile,
        .readsUv = true,
        .readsTangentBasis = [](const Layer&) { return true; },
        .textureSlots = 1,
        .textureSlotsOf = [](const Layer& L) { return L.params<P>().lean ? 2 : 1; },
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_feature.glsl",
        .glslFileOf =
            [](const Layer& L) {
                return L.params<P>().lean ? "sg/render/layer_feature_aa.glsl"
                                          : "sg/render/layer_feature.glsl";
            },
        .antialias = [](const Layer& L) { return L.params<P>().lean; },
        .signature = [](const Layer& L) -> std::string {
            return L.params<P>().lean ? "~lean" : "";
        },
        .assets = &featureKindAssets(),
        .records = {layerRecords(), profileRecords(), aaRecords()},
        .emit = kEmit,
        .batch = &kBatch,
        .programDeclarations = declarations,
        .programDefines =
            [](const MaterialPlan& plan, std::vector<std::string>& defs) {
                const FeaturePlan fp = featurePlan(plan);
                defs.push_back(std::string("SG_FEAT_CURVED ") + (fp.curved ? "1" : "0"));
                if (fp.near) defs.push_back("SG_FEAT_NEAR 1"); // effects on demand
            },
        .programSignature =
            [](const MaterialPlan& plan) {
                const FeaturePlan fp = featurePlan(plan);
                return std::string(fp.curved ? "|featcurved" : "|featstraight") +
                       (fp.near ? "|featnear" : "") + (fp.lean ? "|featlean" : "");
            },
        .imageCases =
            {
                {"feature_curves_surfgrad",
                 R"({"type": "feature", "curves": {"svg": "data/svg/flame.svg", "size": 128}, "profile": "vgroove", "depth": 1.5, "width": 3})"},
                {"feature_curves_paper_with_base",
                 R"({"type": "feature", "curves": {"svg": "data/svg/waves-horizontal.svg", "size": 128}, "profile": "ridge", "depth": 1, "width": 4, "w0": 1, "mode": "paper", "tiling": 2, "base_map": {"procedural": "tiles", "size": 128}})"},
                // The exact near field with per-curve profiles and widths
                // (examples/feature-profiles/curves.json: V-grooves, a ridge, a
                // tapered crease, a table profile) next to a paper-mode layer.
                {"feature_curves_near_exact_per_curve_profiles",
                 R"({"type": "feature", "near": "exact", "curves": {"json": "examples/feature-profiles/curves.json", "size": 96, "mode": "quadratic", "margin": 6}, "profile": "crease", "depth": 1.5, "width": 3}, {"type": "feature", "curves": {"svg": "data/svg/flame.svg", "size": 64}, "profile": "vgroove", "depth": 1, "width": 2, "tiling": 2})"},
            },
    };
    return kind;
}

} // namespace sg::render
