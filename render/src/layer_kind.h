// Layer kinds as units: the interface every bump layer kind implements.
//
// A layer kind is two files plus one line in the registry
// (layer_registry.cpp):
//   shaders/sg/render/layer_<kind>.glsl
//       the shared GLSL/C++ function (sgLayer<Kind>, with a variant per
//       mode that brings code the others must not carry, e.g.
//       sgLayer<Kind>Lean in layer_<kind>_aa.glsl), its parameter struct
//       and its record unpacker sgUnpack<Kind>;
//   render/src/layers/layer_<kind>.cpp
//       the LayerKind entry below: the parameter table (scene fields,
//       validation, viewer sliders, docs), the record layout (the packer,
//       slot by slot beside the GLSL unpacker it must match), the one
//       emitter that binds the function's arguments for both renderers
//       (layer_emit.h), and the scenes that show it (image parity).
// A kind whose layers read data of their own besides textures (feature:
// feature maps) adds the hooks of section 5, usually in a third file
// layers/<kind>_assets.{h,cpp}: loading, plan slots, GL binding, CPU data.
// Everything else (scene parser, planner, assembler, CPU twin, viewer,
// asset loader, uber-shader stand-ins, the record round-trip test, the
// image-parity test) iterates the registry. docs/architecture.md, "Adding a
// layer kind", walks through an example.
//
// Derivative-space modifiers (Loviscach 2008) are units of the same shape,
// one ModifierKind each (render/src/layers/deriv_mods.cpp).
//
// Internal to surfgrad_render (the kind files are compiled by it).
#pragma once

#include <any>
#include <array>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include "render_internal.h"
#include "scene_node.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h"

namespace sg::render {

// ---------------------------------------------------------------------------
// 1. Parameters: one declarative table per kind.
//
// Each entry is one scene field: its JSON name, the member it sets, its type
// and validation range (the parser's messages name the field path, e.g.
// "materials[0].layers[2].strength: expected a number"), an optional viewer
// slider and a doc line (the viewer's tooltip; tests/render checks that
// docs/scene.md names every field of every kind). The table's order is the
// order fields are read (and listed in "unknown field" messages). Bespoke
// code only where a kind needs it: a Custom entry parses its field itself,
// `check` validates after the value is stored (and runs when it is absent).

enum class ParamType { Number, Integer, Boolean, Choice, Vec3, String, Map, Custom };

struct SliderRange {
    float lo = 0.0f, hi = 1.0f;
    const char* format = "%.3f";
};

using ParamParse = std::function<void(const detail::SceneNode& layerNode, const char* key,
                                      Layer& layer, const detail::SceneReader& reader)>;
using ParamCheck =
    std::function<void(const detail::SceneNode& layerNode, const char* key, const Layer& layer)>;

struct ParamSpec {
    const char* json = "";
    ParamType type = ParamType::Custom;
    const char* doc = "";
    double lo = -detail::kHuge, hi = detail::kHuge;   // Number, Integer, Vec3
    bool loOpen = false;                              // Number: (lo, hi]
    std::vector<std::pair<const char*, int>> choices; // Choice: name -> value
    Wrap wrap = Wrap::Repeat;                         // Map
    bool required = false;                            // Map
    std::optional<SliderRange> slider;                // viewer (Number only)
    // Typed access, made by the param:: helpers below.
    std::function<void(Layer&, double)> setNumber;   // Number, Integer, Boolean, Choice
    std::function<void(Layer&, glm::dvec3)> setVec3; // read in binary64
    std::function<void(Layer&, std::string)> setString;
    std::function<float*(Layer&)> floatRef; // Number: the member (viewer sliders)
    ParamParse parse;                       // Custom
    ParamCheck check;                       // optional, any type
    // A layer that does not set the field takes its material's
    // "antialias" (SceneReader::materialAntialias: "none", "lean" or
    // "toksvig") as the value this returns; "" leaves the default
    // (optional: fields that follow the material's default).
    std::function<std::string(const std::string& materialValue, const Layer&)> fromMaterial;
};

namespace param {

// The struct P's member of a layer: P is Layer for the shared fields
// (strength, uv_set), else the kind's parameter struct.
template <class P>
P& owner(Layer& L) {
    if constexpr (std::is_same_v<P, Layer>)
        return L;
    else
        return L.params<P>();
}

struct Range {
    double lo = -detail::kHuge, hi = detail::kHuge;
    bool loOpen = false; // (lo, hi]
};

template <class P>
ParamSpec number(const char* json, float P::*m, Range r, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Number;
    s.doc = doc;
    s.lo = r.lo;
    s.hi = r.hi;
    s.loOpen = r.loOpen;
    s.setNumber = [m](Layer& L, double v) { owner<P>(L).*m = float(v); };
    s.floatRef = [m](Layer& L) { return &(owner<P>(L).*m); };
    return s;
}

template <class P>
ParamSpec integer(const char* json, int P::*m, int lo, int hi, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Integer;
    s.doc = doc;
    s.lo = lo;
    s.hi = hi;
    s.setNumber = [m](Layer& L, double v) { owner<P>(L).*m = int(v); };
    return s;
}

template <class P>
ParamSpec boolean(const char* json, bool P::*m, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Boolean;
    s.doc = doc;
    s.setNumber = [m](Layer& L, double v) { owner<P>(L).*m = v != 0.0; };
    return s;
}

// One of named values, stored as T (an enum, bool or int).
template <class P, class T>
ParamSpec choice(const char* json, T P::*m,
                 std::initializer_list<std::pair<const char*, std::type_identity_t<T>>> values,
                 const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Choice;
    s.doc = doc;
    for (const auto& [name, v] : values) s.choices.emplace_back(name, int(v));
    s.setNumber = [m](Layer& L, double v) { owner<P>(L).*m = static_cast<T>(int(v)); };
    return s;
}

template <class P>
ParamSpec vec3(const char* json, glm::vec3 P::*m, Range r, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Vec3;
    s.doc = doc;
    s.lo = r.lo;
    s.hi = r.hi;
    s.setVec3 = [m](Layer& L, glm::dvec3 v) { owner<P>(L).*m = glm::vec3(v); };
    return s;
}

// A binary64 vector (positions: kept in binary64 until the camera-relative
// composition).
template <class P>
ParamSpec vec3(const char* json, glm::dvec3 P::*m, Range r, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::Vec3;
    s.doc = doc;
    s.lo = r.lo;
    s.hi = r.hi;
    s.setVec3 = [m](Layer& L, glm::dvec3 v) { owner<P>(L).*m = v; };
    return s;
}

template <class P>
ParamSpec string(const char* json, std::string P::*m, const char* doc) {
    ParamSpec s;
    s.json = json;
    s.type = ParamType::String;
    s.doc = doc;
    s.setString = [m](Layer& L, std::string v) { owner<P>(L).*m = std::move(v); };
    return s;
}

// A required texture, appended to Layer::maps.
ParamSpec map(const char* json, Wrap wrap, const char* doc);
// An optional texture, appended to Layer::maps when given.
ParamSpec optionalMap(const char* json, Wrap wrap, const char* doc);
// A field the kind parses itself (or that another entry's parser reads).
ParamSpec custom(const char* json, ParamParse parse, const char* doc);
// The entry with a viewer slider (Number entries).
ParamSpec slider(ParamSpec s, float lo, float hi, const char* format = "%.3f");
// The entry with a check run after it is read.
ParamSpec checked(ParamSpec s, ParamCheck check);

// Shared fields of several kinds.
ParamSpec strength(); // bump scale, slider -3..3
ParamSpec uvSet();    // "uv_set", 0..kMaxUvSets-1
// A texture channel: "r", "g", "b", "a" -> 0..3.
template <class P>
ParamSpec channel(const char* json, int P::*m, const char* doc) {
    return choice(json, m, {{"r", 0}, {"g", 1}, {"b", 2}, {"a", 3}}, doc);
}
// "encoding": rgb, rg, ag, float; twoChannel false: rgb or float only.
template <class P>
ParamSpec encoding(NormalEncoding P::*m, bool twoChannel) {
    ParamSpec s = choice("encoding", m,
                         {{"rgb", NormalEncoding::Rgb},
                          {"rg", NormalEncoding::Rg},
                          {"ag", NormalEncoding::Ag},
                          {"float", NormalEncoding::Float}},
                         "normal-map encoding");
    if (!twoChannel) {
        s.check = [m](const detail::SceneNode& n, const char*, const Layer& L) {
            NormalEncoding e = L.params<P>().*m;
            if (e == NormalEncoding::Rg || e == NormalEncoding::Ag) {
                n.failField("encoding",
                            "this layer needs all three components: expected \"rgb\" or \"float\"");
            }
        };
    }
    return s;
}
// "green": "gl" (up) or "dx" (down: listing 4's flip).
template <class P>
ParamSpec green(bool P::*m) {
    return choice("green", m, {{"gl", false}, {"dx", true}}, "normal-map green convention");
}
// "height": {"channel": "a", "scale": 1}, the height channel modifiers read.
template <class P>
ParamSpec heightChannel(int P::*channelMember, float P::*scaleMember) {
    return custom(
        "height",
        [channelMember, scaleMember](const detail::SceneNode& n, const char* key, Layer& L,
                                     const detail::SceneReader&) {
            if (!n.has(key)) return;
            detail::SceneNode h = n.child(key);
            h.allowOnly({"channel", "scale"});
            L.params<P>().*channelMember = h.choice("channel", 3, {"r", "g", "b", "a"});
            L.params<P>().*scaleMember = h.num("scale", 1.0, -detail::kHuge, detail::kHuge);
        },
        "height channel and scale (read by modifiers)");
}
// "modifiers": derivative-space modifiers (deriv_mods.cpp).
ParamSpec modifiers();

// Bump antialiasing of a kind that reads tangent-space normal maps
// (sg/render/slope_dist.glsl): puts in place of the layer's maps their
// moment textures, `planes` maps (a shorter list repeats its last map) of
// encoding `enc`: per map LEAN's A and B (aa SG_AA_LEAN) or Toksvig's one
// (SG_AA_TOKSVIG). aa 0 or no maps (their own error): unchanged.
void useMomentMaps(Layer& L, int aa, NormalEncoding enc, int planes);
// "antialias": "none" (0), "lean" (SG_AA_LEAN) or "toksvig" (SG_AA_TOKSVIG)
// into P::*aaMember, then the maps become their moment textures
// (useMomentMaps). Read after the maps and the encoding.
template <class P>
ParamSpec antialias(int P::*aaMember, NormalEncoding P::*encMember, int planes) {
    ParamSpec s = custom(
        "antialias",
        [aaMember, encMember, planes](const detail::SceneNode& n, const char* key, Layer& L,
                                      const detail::SceneReader&) {
            if (!n.has(key)) return;
            P& p = L.params<P>();
            p.*aaMember = n.choice(key, 0, {"none", "lean", "toksvig"});
            useMomentMaps(L, p.*aaMember, p.*encMember, planes);
        },
        "bump antialiasing: \"none\" (default), \"lean\" or \"toksvig\" (slope covariance "
        "of the footprint widens the lobe; default: the material's)");
    // The material's value, except on layers with modifiers (which do not
    // antialias).
    s.fromMaterial = [](const std::string& v, const Layer& L) {
        return L.modifiers.empty() ? v : std::string();
    };
    return s;
}

} // namespace param

// ---------------------------------------------------------------------------
// 2. Records: the packer, one declarative layout per GLSL unpacker.
//
// A kind's parameters reach the GPU as vec4 records (uLayerData) that its
// sgUnpack* function reads; the CPU reads the same records. A RecordLayout
// names the unpacker and, per field of its GLSL struct, the slots it reads
// ("r0.xyz", "r1.w r2.w r3.w") and the value packed there, computed from the
// layer. Packing writes exactly these slots (other slots stay 0). The
// round-trip test (tests/render/layer_records_test.cpp) packs random values
// for every field of every layout, unpacks them through the GLSL function on
// the GPU and through its C++ build, and compares field by field: a layout
// and an unpacker that disagree on a slot fail it.

// What a field's value is computed from.
struct PackInput {
    const Layer& layer;
    const View& view;          // decal origins are packed relative to the camera
    const SceneAssets* assets; // nullptr when packing without assets
    const std::any& prepared;  // RecordLayout::prepare's result (or empty)
    template <class P>
    const P& params() const {
        return layer.params<P>();
    }
};

enum class FieldType { Float, Int, Bool, Vec2, Vec3 };
int componentCount(FieldType t);

struct Slot {
    int record = 0;    // relative to the layout's first record
    int component = 0; // 0 x .. 3 w
};

struct RecordField {
    std::string glsl; // member of the GLSL struct, e.g. "origin", "table[3]"
    FieldType type = FieldType::Float;
    std::vector<Slot> slots;                          // one per component
    std::function<glm::vec3(const PackInput&)> value; // ints and bools as exact floats
    // The member of the C++ build's unpacked struct (std::any holding it) as
    // 32-bit words: float bits, int as two's complement, bool 0/1.
    std::function<void(const std::any& unpacked, uint32_t* words)> read;
};

struct RecordLayout {
    std::string structType; // e.g. "SgDecalParams"
    std::string unpack;     // e.g. "sgUnpackDecal"
    int first = 0;          // first record, relative to the layer's
    int count = 0;          // vec4 arguments of the unpacker
    std::vector<RecordField> fields;
    std::function<std::any(const Layer&)> prepare;               // optional: computed once per pack
    std::function<std::any(const glm::vec4* records)> unpackCpu; // the C++ build
    // The same into a struct of type *unpackType (the emitters' CpuRecord).
    std::function<void(const glm::vec4* records, void* out)> unpackTo;
    const std::type_info* unpackType = nullptr;
    std::string glslFile; // file defining the unpacker; empty: the kind's glslFile
};

// Slots "r<i>.<components>" separated by spaces, e.g. "r1.w r2.w r3.w".
std::vector<Slot> parseSlots(const char* text);

// Builds a RecordLayout for the GLSL struct S unpacked by `fn` from N records.
template <class S, int N>
class Records {
public:
    template <class F>
    Records(const char* structType, const char* unpack, F fn, int first = 0) {
        l_.structType = structType;
        l_.unpack = unpack;
        l_.first = first;
        l_.count = N;
        l_.unpackCpu = [fn](const glm::vec4* r) {
            return std::any(call(fn, r, std::make_integer_sequence<int, N>{}));
        };
        l_.unpackTo = [fn](const glm::vec4* r, void* out) {
            *static_cast<S*>(out) = call(fn, r, std::make_integer_sequence<int, N>{});
        };
        l_.unpackType = &typeid(S);
    }
    // Member `m` of S at `slots`, packed from get(PackInput) (a T).
    template <class T, class G>
    Records& field(const char* glsl, T S::*m, const char* slots, G get) {
        return add(
            glsl, typeOf<T>(), slots, [get](const PackInput& in) { return toVec3(T(get(in))); },
            [m](const S& s) { return s.*m; });
    }
    // Element i of the array member `m` of S.
    template <class T, size_t K, class G>
    Records& element(const char* glsl, T (S::*m)[K], size_t i, const char* slots, G get) {
        return add(
            glsl, typeOf<T>(), slots, [get](const PackInput& in) { return toVec3(T(get(in))); },
            [m, i](const S& s) { return (s.*m)[i]; });
    }
    Records& prepare(std::function<std::any(const Layer&)> p) {
        l_.prepare = std::move(p);
        return *this;
    }
    RecordLayout done() const { return l_; }

private:
    template <class F, int... I>
    static S call(F fn, const glm::vec4* r, std::integer_sequence<int, I...>) {
        return fn(r[I]...);
    }
    template <class T>
    static FieldType typeOf() {
        if constexpr (std::is_same_v<T, float>) return FieldType::Float;
        if constexpr (std::is_same_v<T, int>) return FieldType::Int;
        if constexpr (std::is_same_v<T, bool>) return FieldType::Bool;
        if constexpr (std::is_same_v<T, glm::vec2>) return FieldType::Vec2;
        if constexpr (std::is_same_v<T, glm::vec3>) return FieldType::Vec3;
    }
    static glm::vec3 toVec3(float x) { return glm::vec3(x, 0.0f, 0.0f); }
    static glm::vec3 toVec3(int x) { return glm::vec3(float(x), 0.0f, 0.0f); }
    static glm::vec3 toVec3(bool x) { return glm::vec3(x ? 1.0f : 0.0f, 0.0f, 0.0f); }
    static glm::vec3 toVec3(glm::vec2 x) { return glm::vec3(x, 0.0f); }
    static glm::vec3 toVec3(glm::vec3 x) { return x; }
    static void words(float x, uint32_t* w) { std::memcpy(w, &x, 4); }
    static void words(int x, uint32_t* w) { w[0] = uint32_t(x); }
    static void words(bool x, uint32_t* w) { w[0] = x ? 1u : 0u; }
    static void words(glm::vec2 x, uint32_t* w) { std::memcpy(w, &x[0], 8); }
    static void words(glm::vec3 x, uint32_t* w) { std::memcpy(w, &x[0], 12); }
    template <class R>
    Records& add(const char* glsl, FieldType type, const char* slots,
                 std::function<glm::vec3(const PackInput&)> value, R readMember) {
        RecordField f;
        f.glsl = glsl;
        f.type = type;
        f.slots = parseSlots(slots);
        SG_ASSERT(int(f.slots.size()) == componentCount(type), "one slot per component");
        f.value = std::move(value);
        f.read = [readMember](const std::any& u, uint32_t* w) {
            words(readMember(std::any_cast<const S&>(u)), w);
        };
        l_.fields.push_back(std::move(f));
        return *this;
    }
    RecordLayout l_;
};

// Writes one field's value into its slots (the packer; records[0] is the
// layout's first record).
void packField(const RecordField& f, glm::vec3 value, glm::vec4* records);
// Packs every field of every layout of the layer's kind into `records`
// (the layer's first record).
void packLayer(const Layer& L, const View& view, const SceneAssets* assets, glm::vec4* records);

// ---------------------------------------------------------------------------
// 3. Emission: one emitter, the GLSL statement and the CPU call (layer_emit.h).
//
// The assembled main() (plan.cpp, fragmentBody) holds these variables, and the CPU
// twin the same ones in CpuShadeState: `frame` (SgFrame: the prologue,
// listing 16, or the re-prologue of a post-resolve group), `uv0`..`uv3`
// (SgUvFrame of each UV set the plan reads), `volWorld`, `volObject`
// (SgVolumeSpace, when a layer uses them), `surfGrad` (the group's sum),
// and in plans that antialias, `slopeCov` (mat3: the frame-space slope
// covariances of the layers so far, every group's, sg/render/antialias.glsl).
// A kind's statement adds its surface gradient to surfGrad; a kind may also
// replace frames for the layers after it (e.g. assign uv<k> a corrected
// coordinate, or `frame` a virtual surface followed by sgReprologue), as
// long as its CPU call does the same to the state. One statement: a block
// `{ ... }` when it needs locals (the assembler may guard it with an `if`
// in uber-shaders).
//
// Moving the surface (LayerKind::movesSurface: parallax, POM; Mikkelsen
// 2019, sections 2.6 and 3): main() then also holds `surfOffset` (vec3,
// frame space, initially 0), the offset of the virtual surface from the
// mesh surface, which such a kind's statement adds to; the base colour is
// sampled after group 0's layers (so it reads corrected coordinates); and
// the re-prologue of every later group is the `reprologue` statement of the
// last such layer before it (nrm, the resolved normal, in scope) instead of
// the default sgReprologue(frame, nrm, frame.dPdx, frame.dPdy): it sets
// `frame` to the virtual surface (e.g. listing 17's analytic derivatives at
// vRelPos + surfOffset), sets `surfPos` (vec3, camera-relative: the
// position of the frame's surface, vRelPos until then) to the virtual
// surface and rebuilds volWorld/volObject there (when the plan uses them).
// Position-projected layers (decal) read surfPos (GlslLayerContext::relPos,
// CpuShadeState::surfPos), so their detail lands on the virtual surface
// like the volume layers' (section 3, Fig. 3(d)). The UV frames of the
// group are rebuilt after it as usual.

struct GlslLayerContext {
    const MaterialPlan& plan;
    const PlanLayer& pl;
    std::string indent; // of the statement; lines inside a block add 4 spaces
    // The statement is the body of a batch's loop over its layers (LayerBatch):
    // records are read from `r` (the loop's record index of layer fi) and the
    // UV frame is `fuv`; pl stands for every layer of the batch, so the
    // emitter reads only plan-level modes then.
    bool loop = false;

    const Layer& layer() const { return *pl.layer; }
    std::string rec(int i) const;                    // "uLayerData[n]", i relative to the layer
    std::string unpack(const RecordLayout& l) const; // "sgUnpackX(uLayerData[a], ...)"
    std::string tex(int i) const;                    // "uTex<slot>" of the layer's i-th texture
    std::string uv() const;                          // "uv<k>": the layer's UV frame
    std::string vol(Space s) const;                  // "volWorld" | "volObject"
    // The position of the frame's surface, camera-relative: "surfPos" in
    // plans that move the surface (the virtual surface after a re-prologue),
    // else "vRelPos".
    std::string relPos() const;
};

// The shader files a plan's layers include, in first-use order: each
// layer's kind file (its options' variant, or its modifier file), then
// sg/render/antialias.glsl when the plan antialiases (plan.cpp).
std::vector<std::string> layerGlslFiles(const MaterialPlan& plan);

// A layer of the plan moves the surface (LayerKind::movesSurface).
bool planMovesSurface(const MaterialPlan& plan);

// The main()'s variables on the CPU.
struct CpuShadeState {
    sg::glsl::SgFrame frame{};
    std::array<sg::glsl::SgUvFrame, kMaxUvSets> uv{};
    sg::glsl::SgVolumeSpace volWorld{}, volObject{};
    glm::vec3 surfGrad{0.0f};
    glm::mat3 slopeCov{0.0f};   // antialiasing plans: the sum of the layers' slope covariances
    glm::vec3 surfOffset{0.0f}; // the virtual surface (LayerKind::movesSurface)
    // The position of the frame's surface (GLSL surfPos): the pixel's
    // relPos from the prologue, the virtual surface after a re-prologue.
    glm::vec3 surfPos{0.0f};
    const sg::glsl::SgVolumeSpace& vol(Space s) const {
        return s == Space::World ? volWorld : volObject;
    }
};

struct CpuLayerContext {
    const MaterialPlan& plan;
    const PlanLayer& pl;
    const detail::DrawUniforms& u;
    const std::vector<sg::glsl::sampler2D>& samplers;
    // The kind's per-plan CPU data (LayerKindAssets::cpuData; nullptr: none).
    const std::any* kindData;
    const detail::PixelInputs& in;

    const Layer& layer() const { return *pl.layer; }
    const glm::vec4* rec() const { return &u.records[size_t(pl.record)]; }
    sg::glsl::sampler2D tex(int i) const {
        int slot = pl.tex[i];
        return slot >= 0 ? samplers[size_t(slot)] : sg::glsl::sampler2D{};
    }
    const sg::glsl::SgUvFrame& uv(const CpuShadeState& s) const {
        return s.uv[size_t(pl.layer->uvSet)];
    }
};

// A kind's statement for both renderers, made by emitter() (layer_emit.h)
// from one generic lambda: the GLSL statement of the assembled main(), and
// the CPU call on the twin's state (nrm: the resolved normal, for
// re-prologues).
struct LayerEmitter {
    std::string (*glsl)(const GlslLayerContext&) = nullptr;
    void (*cpu)(const CpuLayerContext&, CpuShadeState&, glm::vec3 nrm) = nullptr;
    explicit operator bool() const { return cpu != nullptr; }
};

// Kinds emitted together per group rather than one statement per layer
// (feature: one loop, so the large evaluator is compiled once). The CPU
// twin calls shadeCpu per layer in the loop's order: after the group's
// other layers, batched kinds in registry order, each kind's layers in
// plan order.
struct LayerBatch {
    std::string (*groupStatements)(const MaterialPlan& plan,
                                   const std::vector<const PlanLayer*>& layers,
                                   const std::string& indent) = nullptr;
};

// ---------------------------------------------------------------------------
// 4. Derivative-space modifiers (render/src/layers/deriv_mods.cpp).

// A kind that takes modifiers samples its map as a height and derivative,
// lets the modifiers edit them, then turns the derivative into its surface
// gradient: its emitter calls addDerivModSurfgrad (layer_emit.h) with those
// two steps; the modifiers between them come from their ModifierKind.
struct DerivModTarget {
    const char* glslFile; // the kind's file with the HD sampler (included instead)
};

// A modifier's statement, one generic lambda instantiated for both binders
// (modifierEmitter, layer_emit.h): edits `hd` (SgHeightDeriv) with the
// modifier's inputs (ModifierArgs: its record `op`, its mask, the lookup
// st/dx/dy and the lookup warp's Jacobian `jac`).
class GlslBinder;
class CpuBinder;
struct GlslExpr;
template <class Binder>
struct ModifierArgs;
struct ModifierEmitter {
    void (*glsl)(GlslBinder&, GlslExpr& hd, const ModifierArgs<GlslBinder>&) = nullptr;
    void (*cpu)(CpuBinder&, sg::glsl::SgHeightDeriv& hd, const ModifierArgs<CpuBinder>&) = nullptr;
};
// A lookup warp (ModifierKind::warpsLookup): sets st, dx, dy and jac of the
// arguments from the layer's UV frame and `op` (modifierWarp, layer_emit.h).
struct ModifierWarp {
    void (*glsl)(GlslBinder&, ModifierArgs<GlslBinder>&) = nullptr;
    void (*cpu)(CpuBinder&, ModifierArgs<CpuBinder>&) = nullptr;
};

struct ModifierKind {
    const char* name = "";           // the scene's "type"
    int id = 0;                      // SG_MOD_* (record x)
    char sigCode = '?';              // in the effect signature
    std::vector<const char*> fields; // scene fields besides "type"
    const char* doc = "";
    bool warpsLookup = false; // acts on the lookup: must be the first modifier
    void (*parse)(const detail::SceneNode& n, Modifier& m,
                  const detail::SceneReader& reader) = nullptr;
    glm::vec4 (*pack)(const Modifier&) = nullptr;
    ModifierWarp warp;    // warpsLookup: the warped lookup
    ModifierEmitter emit; // "hd = sgModX(hd, op...);" and its CPU twin
};

const std::vector<const ModifierKind*>& modifierKinds();

// The GLSL name of an antialiasing mode (SG_AA_LEAN, SG_AA_TOKSVIG).
constexpr const char* aaName(int aa) {
    return aa == SG_AA_LEAN ? "SG_AA_LEAN" : aa == SG_AA_TOKSVIG ? "SG_AA_TOKSVIG" : "0";
}

// Texture components as LayerKind::mapChannels bits.
constexpr uint32_t kChannelR = 1, kChannelG = 2, kChannelB = 4, kChannelA = 8;
constexpr uint32_t kRgbaChannels = kChannelR | kChannelG | kChannelB | kChannelA;
// The components a tangent-space normal encoding stores x and y in
// (sgDecodeNormalXY: z is rebuilt, ag maps keep x in alpha).
constexpr uint32_t normalXyChannels(NormalEncoding e) {
    return e == NormalEncoding::Ag ? (kChannelG | kChannelA) : (kChannelR | kChannelG);
}
// One component 0..3 (r..a) as a mask; none for a negative channel.
constexpr uint32_t channelBit(int channel) {
    return channel >= 0 ? 1u << channel : 0u;
}

// ---------------------------------------------------------------------------
// 5. A kind's own assets (optional): data its layers read besides the
// textures of Layer::maps (feature: the feature maps, layers/feature_assets.h),
// owned by the kind's files from loading to binding. The generic code only
// iterates the registry and calls these hooks: the asset loader (load; a
// texture a kind makes from them is a TextureSource with a producer), the
// planner (plan: slots in the plan's KindPlan of the kind), the GL renderer
// (gpuUnits, bindGpu: texture units after the plan's regular textures, in
// the order of plan.kindPlans) and the CPU twin (cpuData, read by the
// kind's cpu() through CpuLayerContext::kindData). A kind's assets are
// read clamped at their border: the UV set of a layer reading them is not
// re-centred as a repeating one (uv_sets.cpp).

// The GL renderer's binding of one kind's assets for one draw.
struct KindGpuContext {
    const MaterialPlan& plan;
    const KindPlan& kindPlan; // the kind's entry of plan.kindPlans
    const SceneAssets& assets;
    // The kind's GL objects in this renderer: made by the hook on first use,
    // kept across frames, destroyed with the renderer (its context current).
    std::shared_ptr<void>& cache;
    int firstUnit = 0; // the kind's texture units: firstUnit .. + gpuUnits - 1
    // Location of a uniform of the program in use (-1: not in it); empty:
    // upload only (before the timed draws), bind nothing.
    std::function<int(const char*)> uniform;
};

struct LayerKindAssets {
    // The layer reads assets of its kind (an enabled layer that does is
    // loaded and planned with the hooks below).
    bool (*reads)(const Layer&) = nullptr;
    // Loads what `layers` (the enabled layers of the kind that read assets,
    // of the materials some mesh uses, in order, children included) need and
    // `assets` lacks into assets.kindAssets[kind name] (appending to
    // assets.log), then checks each layer against them. Errors:
    // InputError naming scene.sourceName and the field.
    void (*load)(const Scene& scene, const std::vector<const Layer*>& layers,
                 SceneAssets& assets) = nullptr;
    // Plans layer `L` (reads(L)) into the kind's KindPlan `kp` (made empty
    // for the kind's first layer in the plan): its slot among kp.keys
    // (pl.kindSlot), its index kp.layerCount++ (pl.kindIndex) and kp.data.
    void (*plan)(const Layer& L, const SceneAssets& assets, KindPlan& kp, PlanLayer& pl) = nullptr;
    char slotCode = '?'; // effect signature: a layer's slot as <slotCode><kindSlot>
    // GL: the texture units the kind's share of a plan takes, and the
    // upload (once per renderer, into the context's cache) and binding of
    // its assets with the uniforms of the plan's layers of the kind.
    int (*gpuUnits)(const KindPlan& kp) = nullptr;
    void (*bindGpu)(const KindGpuContext& c) = nullptr;
    // CPU: what the kind's cpu() reads (CpuLayerContext::kindData), made
    // once per plan from the loaded assets.
    std::any (*cpuData)(const KindPlan& kp, const SceneAssets& assets) = nullptr;
};

// The kind's KindPlan in `plan` (nullptr: no layer of it reads assets).
const KindPlan* findKindPlan(const MaterialPlan& plan, const LayerKind& kind);

// ---------------------------------------------------------------------------
// 6. The kind.

// A scene that shows the kind, drawn by both renderers and compared
// (tests/render/image_test.cpp, "Kinds/LayerImage": every registered kind
// has at least one): one material of `layers` (JSON array elements) on
// `mesh` (JSON; empty: a sphere of radius 1), 200 x 150 pixels. Relative
// paths are relative to the source folder.
struct KindImageCase {
    const char* name = "";        // the test's name (letters, digits, '_')
    std::string layers;           // the material's layers
    std::string mesh;             // the mesh ("" : the sphere)
    std::string sceneExtra;       // more top-level scene members, e.g. `, "camera": {...}`
    double referenceP99Deg = 4.0; // the exact-derivative comparison's p99 bound
};

struct LayerKind {
    const char* name = "";    // the scene's "type"
    const char* sigCode = ""; // the kind in the effect signature
    const char* doc = "";     // one line: what it is, which listing
    // A minimal layer of the kind: its required fields as JSON object
    // members (without "type"), e.g. "\"map\": \"n.png\"" (tests, docs).
    const char* example = "";
    std::vector<ParamSpec> params;
    std::any (*makeParams)() = nullptr; // default parameters (nullptr: none)
    // Cross-field validation after every entry was read (optional).
    void (*check)(const detail::SceneNode& n, const Layer& L) = nullptr;

    // What the planner needs.
    bool group = false;   // a post-resolve group of layers (post_resolve)
    bool readsUv = false; // reads Layer::uvSet's frame
    bool (*readsTangentBasis)(const Layer&) = nullptr; // the frame's vT, vB (vertex tangents)
    int textureSlots = 0; // Layer::maps[i] -> slot i (missing maps repeat the last)
    // The layer's slot count when it depends on its options (optional;
    // overrides textureSlots; at most 6, PlanLayer::tex).
    int (*textureSlotsOf)(const Layer&) = nullptr;
    // The components of its maps the kind's shader reads (bit c: component
    // c of RGBA; sgDecodeNormalXY/XYZ and sgTexelChannel in common.glsl) and
    // what reads them, for messages. Textures are decoded with only these
    // (assets.cpp); nullptr: all four.
    uint32_t (*mapChannels)(const Layer&, const char*& why) = nullptr;
    std::optional<Space> (*volume)(const Layer&) = nullptr; // a volume domain
    const char* glslFile = nullptr;                         // #included when used
    // The file a layer with these options includes instead (optional, e.g.
    // its antialiased variant; nullptr: glslFile).
    const char* (*glslFileOf)(const Layer&) = nullptr;
    // The layer adds the covariance of its slopes to `slopeCov` (bump
    // antialiasing, sg/render/antialias.glsl): the program then declares
    // slopeCov and widens the shading lobe by it (optional).
    bool (*antialias)(const Layer&) = nullptr;
    // What else the layer's GLSL statement depends on besides its records
    // (compile-time options): appended to its code in the effect signature,
    // so programs that differ are cached apart (optional).
    std::string (*signature)(const Layer&) = nullptr;
    const DerivModTarget* modifiers = nullptr; // takes derivative-space modifiers
    // The kind's own assets (section 5; optional).
    const LayerKindAssets* assets = nullptr;
    std::vector<RecordLayout> records;

    // Emission (section 3): one emitter for both renderers (layer_emit.h).
    // A batched kind's GLSL is its batch's; its emitter gives the CPU call.
    LayerEmitter emit;
    const LayerBatch* batch = nullptr;
    // The statement moves the surface (section 3 above): surfOffset, late
    // base colour, and `reprologue` (optional) for the groups after it; the
    // CPU twin sets the state's frame and volumes the same way (the
    // binder's resolvedNormal(): the resolved normal of the group before).
    bool movesSurface = false;
    LayerEmitter reprologue;
    // Once per program when the plan has layers of this kind: declarations
    // after the texture uniforms, #defines, and a part of the signature.
    std::string (*programDeclarations)(const MaterialPlan&) = nullptr;
    void (*programDefines)(const MaterialPlan&, std::vector<std::string>&) = nullptr;
    std::string (*programSignature)(const MaterialPlan&) = nullptr;

    // The uber-shader baseline's stand-ins (disabled layers of this kind).
    std::vector<Layer> (*uberStandIns)(const LayerKind& self, int uvCount) = nullptr;
    // Scenes that show the kind (both renderers compared; at least one).
    std::vector<KindImageCase> imageCases;

    int recordCount() const;
};

// The registry, in schema order (layer_registry.cpp).
const std::vector<const LayerKind*>& layerKinds();
Layer makeLayer(const LayerKind& kind);
// A stand-in of an uber plan: a disabled layer of the kind with its defaults.
Layer uberStandIn(const LayerKind& kind);

// Reads a layer's kind-specific fields (the table, then the kind's check).
void parseLayerParams(const LayerKind& kind, const detail::SceneNode& n, Layer& L,
                      const detail::SceneReader& reader);

} // namespace sg::render
