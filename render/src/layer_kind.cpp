// The machinery shared by every layer kind (layer_kind.h): reading a kind's
// parameter table from a scene, packing its record layouts, the names a
// kind's GLSL statement uses, and the registry's queries.
#include "layer_kind.h"

#include <algorithm>

namespace sg::render {

// ---------------------------------------------------------------------------
// Parameters

namespace param {

ParamSpec map(const char* json, Wrap wrap, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Map;
    s.doc = doc;
    s.wrap = wrap;
    s.required = true;
    return s;
}

ParamSpec optionalMap(const char* json, Wrap wrap, const char* doc) {
    ParamSpec s = map(json, wrap, doc);
    s.required = false;
    return s;
}

void useMomentMaps(Layer& L, int aa, NormalEncoding enc, int planes) {
    if (aa == 0 || L.maps.empty()) return;
    std::vector<TextureSource> moments;
    for (int i = 0; i < planes; ++i) {
        TextureSource map = L.maps[std::min(size_t(i), L.maps.size() - 1)];
        map.momentsEncoding = enc;
        if (aa == SG_AA_LEAN) {
            map.moments = TexMoments::LeanA;
            moments.push_back(map);
            map.moments = TexMoments::LeanB;
            moments.push_back(map);
        } else {
            map.moments = TexMoments::Toksvig;
            moments.push_back(map);
        }
    }
    L.maps = std::move(moments);
}

ParamSpec custom(const char* json, ParamParse parse, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Custom;
    s.doc = doc;
    s.parse = std::move(parse);
    return s;
}

ParamSpec slider(ParamSpec s, float lo, float hi, const char* format) {
    SG_ASSERT(s.type == ParamType::Number, "sliders edit numbers");
    s.slider = SliderRange{lo, hi, format};
    return s;
}

ParamSpec checked(ParamSpec s, ParamCheck check) {
    s.check = std::move(check);
    return s;
}

ParamSpec strength() {
    return slider(
        number("strength", &Layer::strength, {}, "bump scale (listing 2; negative inverts)"), -3.0f,
        3.0f);
}

ParamSpec uvSet() {
    return integer("uv_set", &Layer::uvSet, 0, kMaxUvSets - 1, "the UV set the layer reads");
}

} // namespace param

namespace {

void parseParam(const ParamSpec& p, const detail::SceneNode& n, Layer& L,
                const detail::SceneReader& reader) {
    const char* key = p.json;
    if (p.fromMaterial && !reader.materialAntialias.empty() && !n.has(key)) {
        // The material's default, read as if the layer said it.
        const std::string v = p.fromMaterial(reader.materialAntialias, L);
        if (v.empty()) return;
        nlohmann::json withDefault = n.value();
        withDefault[key] = v;
        p.parse(detail::SceneNode(withDefault, n.path(), reader.file), key, L, reader);
        return;
    }
    switch (p.type) {
    case ParamType::Number:
        if (n.has(key)) p.setNumber(L, n.number(key, 0.0, p.lo, p.hi, p.loOpen));
        break;
    case ParamType::Integer:
        if (n.has(key)) p.setNumber(L, n.integer(key, 0, int(p.lo), int(p.hi)));
        break;
    case ParamType::Boolean:
        if (n.has(key)) p.setNumber(L, n.boolean(key, false) ? 1.0 : 0.0);
        break;
    case ParamType::Choice:
        if (n.has(key)) {
            std::vector<const char*> names;
            for (const auto& c : p.choices) names.push_back(c.first);
            p.setNumber(L, p.choices[size_t(n.choice(key, 0, names))].second);
        }
        break;
    case ParamType::Vec3:
        if (n.has(key)) p.setVec3(L, n.dvec3(key, glm::dvec3(0.0), p.lo, p.hi));
        break;
    case ParamType::String:
        if (n.has(key)) p.setString(L, n.string(key, ""));
        break;
    case ParamType::Map:
        if (!n.has(key)) {
            if (p.required) n.fail(std::string("missing \"") + key + "\"");
        } else {
            L.maps.push_back(reader.texture(n.child(key), p.wrap));
        }
        break;
    case ParamType::Custom:
        if (p.parse) p.parse(n, key, L, reader);
        break;
    }
    if (p.check) p.check(n, key, L);
}

} // namespace

void parseLayerParams(const LayerKind& kind, const detail::SceneNode& n, Layer& L,
                      const detail::SceneReader& reader) {
    std::vector<const char*> allowed = {"type", "enabled"};
    for (const ParamSpec& p : kind.params) allowed.push_back(p.json);
    n.allowOnly(allowed);
    for (const ParamSpec& p : kind.params) parseParam(p, n, L, reader);
    if (kind.check) kind.check(n, L);
}

// ---------------------------------------------------------------------------
// Records

int componentCount(FieldType t) {
    switch (t) {
    case FieldType::Vec2:
        return 2;
    case FieldType::Vec3:
        return 3;
    default:
        return 1;
    }
}

std::vector<Slot> parseSlots(const char* text) {
    std::vector<Slot> out;
    const std::string s(text);
    size_t i = 0;
    while (i < s.size()) {
        if (s[i] == ' ') {
            ++i;
            continue;
        }
        SG_ASSERT(s[i] == 'r', "slots read r<record>.<components>");
        size_t dot = s.find('.', i);
        SG_ASSERT(dot != std::string::npos, "slots read r<record>.<components>");
        int record = std::stoi(s.substr(i + 1, dot - i - 1));
        for (i = dot + 1; i < s.size() && s[i] != ' '; ++i) {
            static const std::string xyzw = "xyzw";
            size_t c = xyzw.find(s[i]);
            SG_ASSERT(c != std::string::npos, "components are x, y, z, w");
            out.push_back(Slot{record, int(c)});
        }
    }
    return out;
}

void packField(const RecordField& f, glm::vec3 value, glm::vec4* records) {
    for (size_t i = 0; i < f.slots.size(); ++i)
        records[f.slots[i].record][f.slots[i].component] = value[int(i)];
}

void packLayer(const Layer& L, const View& view, const SceneAssets* assets, glm::vec4* records) {
    for (const RecordLayout& l : L.kind->records) {
        std::any prepared = l.prepare ? l.prepare(L) : std::any();
        PackInput in{L, view, assets, prepared};
        for (const RecordField& f : l.fields) packField(f, f.value(in), records + l.first);
    }
}

int LayerKind::recordCount() const {
    int n = 0;
    for (const RecordLayout& l : records) n = std::max(n, l.first + l.count);
    return n;
}

// ---------------------------------------------------------------------------
// Emission

std::string GlslLayerContext::rec(int i) const {
    if (loop) return i == 0 ? "uLayerData[r]" : "uLayerData[r + " + std::to_string(i) + "]";
    return "uLayerData[" + std::to_string(pl.record + i) + "]";
}

std::string GlslLayerContext::unpack(const RecordLayout& l) const {
    std::string s = l.unpack + "(";
    for (int i = 0; i < l.count; ++i) s += (i ? ", " : "") + rec(l.first + i);
    return s + ")";
}

std::string GlslLayerContext::tex(int i) const {
    return "uTex" + std::to_string(pl.tex[i]);
}

std::string GlslLayerContext::uv() const {
    if (loop) return "fuv";
    return "uv" + std::to_string(pl.layer->uvSet);
}

std::string GlslLayerContext::vol(Space s) const {
    return s == Space::World ? "volWorld" : "volObject";
}

std::string GlslLayerContext::relPos() const {
    return planMovesSurface(plan) ? "surfPos" : "vRelPos";
}

bool planMovesSurface(const MaterialPlan& plan) {
    return std::any_of(plan.kinds.begin(), plan.kinds.end(),
                       [](const LayerKind* k) { return k->movesSurface; });
}

// ---------------------------------------------------------------------------
// Registry queries

const LayerKind* findLayerKind(std::string_view name) {
    for (const LayerKind* k : layerKinds())
        if (name == k->name) return k;
    return nullptr;
}

const char* layerKindName(const LayerKind* kind) {
    return kind ? kind->name : "?";
}

std::vector<LayerSlider> layerSliders(Layer& layer) {
    std::vector<LayerSlider> out;
    if (!layer.kind) return out;
    for (const ParamSpec& p : layer.kind->params) {
        if (!p.slider) continue;
        out.push_back(
            {p.json, p.doc, p.floatRef(layer), p.slider->lo, p.slider->hi, p.slider->format});
    }
    return out;
}

bool layerIsGroup(const Layer& layer) {
    return layer.kind && layer.kind->group;
}

Layer makeLayer(const LayerKind& kind) {
    Layer L;
    L.kind = &kind;
    if (kind.makeParams) L.kindParams = kind.makeParams();
    return L;
}

Layer makeLayer(std::string_view kindName) {
    const LayerKind* k = findLayerKind(kindName);
    SG_EXPECTS(k != nullptr, "makeLayer: a registered layer kind");
    return makeLayer(*k);
}

Layer uberStandIn(const LayerKind& kind) {
    Layer L = makeLayer(kind);
    L.fieldPath = std::string("(uber ") + kind.name + ")";
    L.enabled = false; // compiled in, switched off by its uniform flag
    return L;
}

bool Layer::is(std::string_view kindName) const {
    return kind && kindName == kind->name;
}

const ModifierKind* findModifierKind(std::string_view name) {
    for (const ModifierKind* k : modifierKinds())
        if (name == k->name) return k;
    return nullptr;
}

bool Modifier::is(std::string_view kindName) const {
    return kind && kindName == kind->name;
}

const KindPlan* findKindPlan(const MaterialPlan& plan, const LayerKind& kind) {
    for (const KindPlan& kp : plan.kindPlans)
        if (kp.kind == &kind) return &kp;
    return nullptr;
}

} // namespace sg::render
