// One emitter per layer kind: a kind writes how it calls its shared GLSL
// function (sgLayer<Kind>, sg/render/layer_<kind>.glsl) once, as a generic
// lambda over a binder, and the two renderers instantiate it:
//
//   GlslBinder  writes the assembled main()'s statement: every value is a
//               GLSL expression (GlslExpr: "uv1", "uTex3",
//               "sgUnpackDecal(uLayerData[4], ...)", "slopeCov");
//   CpuBinder   runs the same call on the CPU twin's state (CpuShadeState):
//               every value is the C++ value the expression stands for, and
//               the function is the C++ build of the same GLSL source.
//
// So a kind's modes (antialiasing, near field, occlusion, ...) are branches
// of C++ code that runs when the program is assembled, written once, and
// become compile-time constants of the one GLSL call (binder.constant) or the
// choice of the shared function; glsl() and cpu() only bind arguments.
//
//   .emit = emitter([](auto& b) {
//       b.addSurfgrad(SG_LAYER_CALL(b, sgLayerHeight, b.frame(), b.uv(),
//                                   b.record(), b.tex(0)));
//   }),
//
// What a binder offers (both return the same thing in their terms):
//   layer(), plan()                     the layer and its plan (modes are read here)
//   context()                           the binder's context (a kind's own data:
//                                       LayerKindAssets, e.g. the feature maps)
//   frame(), uv(), vol(space), surfPos(), surfOffset(), slopeCov()
//                                       the main()'s variables (layer_kind.h, section 3);
//                                       references on the CPU, so calls may write them
//   record(i)                           RecordLayout i unpacked (its GLSL unpacker)
//   tex(i)                              the layer's i-th texture
//   constant(v), constant(v, name)      a compile-time constant (int or bool; GLSL
//                                       writes `name`, e.g. "SG_AA_LEAN", when given)
//   vertexNormal(), vertexNormalDx/Dy() the interpolated normal and its screen derivatives
//   fragCoordX/Y(), relPos(), objPos()  gl_FragCoord.x, .y, vRelPos, vObjPos
//   identity3()                         mat3(1.0) (main()'s GLSL only: a splat
//                                       constructor, not part of the shared subset)
//   normalMat(), model3(), modelInv3()  the draw's uniforms
//   resolvedNormal()                    `nrm` (re-prologues)
//   declare(type, name, init)           a local (GLSL declaration; the CPU's value)
//   call(...) through SG_LAYER_CALL     the shared function, by name and by C++ build
//   run(...) through SG_LAYER_RUN       the same as a statement (out arguments)
//   addSurfgrad(g), assign(lhs, rhs)    the statement's effects
//   local(type, name, init)             an initialised local
//   hasModifiers(), modifierRecord(i), modifierMask(i), uvSt/Dx/Dy(), identity2()
//                                       derivative-space modifiers (addDerivModSurfgrad)
// GlslExpr has +, - and * so arithmetic between bound values reads the same
// in both (GLSL's and glm's operators).
//
// Internal to surfgrad_render.
#pragma once

#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

#include "layer_kind.h"

namespace sg::render {

// A GLSL expression, as text (parenthesised where an operator made it).
// The operators have GLSL's meaning (a matrix times a vector is a matrix
// product): a layer statement that engines may paste into HLSL through
// sg/compat.hlsl calls a shared function instead (e.g. sgModWarpDeriv);
// only main()'s own GLSL (the parallax re-prologue) multiplies matrices.
struct GlslExpr {
    std::string text;
};
inline GlslExpr operator+(const GlslExpr& a, const GlslExpr& b) {
    return {"(" + a.text + " + " + b.text + ")"};
}
inline GlslExpr operator-(const GlslExpr& a, const GlslExpr& b) {
    return {"(" + a.text + " - " + b.text + ")"};
}
inline GlslExpr operator*(const GlslExpr& a, const GlslExpr& b) {
    return {"(" + a.text + " * " + b.text + ")"};
}
inline GlslExpr operator-(const GlslExpr& a) {
    return {"-" + a.text};
}

class GlslBinder {
public:
    explicit GlslBinder(const GlslLayerContext& c) : c_(c) {}

    const Layer& layer() const { return c_.layer(); }
    const MaterialPlan& plan() const { return c_.plan; }
    const GlslLayerContext& context() const { return c_; }

    GlslExpr frame() const { return {"frame"}; }
    GlslExpr uv() const { return {c_.uv()}; }
    GlslExpr vol(Space s) const { return {c_.vol(s)}; }
    GlslExpr surfPos() const { return {c_.relPos()}; }
    GlslExpr surfOffset() const { return {"surfOffset"}; }
    GlslExpr slopeCov() const { return {"slopeCov"}; }
    GlslExpr record(size_t layout = 0) const { return {c_.unpack(layer().kind->records[layout])}; }
    GlslExpr tex(int i) const { return {c_.tex(i)}; }
    GlslExpr constant(int v) const { return {std::to_string(v)}; }
    GlslExpr constant(int, const char* glslName) const { return {glslName}; }
    GlslExpr constant(bool v) const { return {v ? "true" : "false"}; }
    GlslExpr vertexNormal() const { return {"vNormal"}; }
    GlslExpr vertexNormalDx() const { return {"SG_DFDX(vNormal)"}; }
    GlslExpr vertexNormalDy() const { return {"SG_DFDY(vNormal)"}; }
    GlslExpr fragCoordX() const { return {"gl_FragCoord.x"}; }
    GlslExpr fragCoordY() const { return {"gl_FragCoord.y"}; }
    GlslExpr identity3() const { return {"mat3(1.0)"}; }
    GlslExpr relPos() const { return {"vRelPos"}; }
    GlslExpr objPos() const { return {"vObjPos"}; }
    GlslExpr normalMat() const { return {"uNormalMat"}; }
    GlslExpr model3() const { return {"uModel3"}; }
    GlslExpr modelInv3() const { return {"uModelInv3"}; }
    GlslExpr resolvedNormal() const { return {"nrm"}; }
    bool hasModifiers() const { return c_.pl.hasModifiers; }
    GlslExpr uvSt() const { return {c_.uv() + ".st"}; }
    GlslExpr uvDx() const { return {c_.uv() + ".dSTdx"}; }
    GlslExpr uvDy() const { return {c_.uv() + ".dSTdy"}; }
    // The identity Jacobian of an unwarped lookup (sgModNoWarp: GLSL's
    // mat2(1.0f) would read as a matrix of ones through sg/compat.hlsl).
    GlslExpr identity2() const { return {"sgModNoWarp()"}; }
    GlslExpr modifierRecord(size_t i) const {
        return {"uLayerData[" + std::to_string(c_.pl.modRecord + int(i)) + "]"};
    }
    GlslExpr modifierMask(size_t i) const {
        const int slot = c_.pl.modTex[i];
        return {slot >= 0 ? "uTex" + std::to_string(slot) : ""};
    }

    // `type name;` (GLSL locals start undefined: only out arguments fill them).
    template <class T>
    GlslExpr declare(const char* type, const char* name, const T&) {
        lines_.push_back(std::string(type) + " " + name + ";");
        return {name};
    }
    // The shared function `name` applied to the arguments (SG_LAYER_CALL).
    template <class F, class... A>
    GlslExpr call(const char* name, F&&, const A&... args) const {
        std::string s = std::string(name) + "(";
        const char* sep = "";
        ((s += sep + text(args), sep = ", "), ...);
        return {s + ")"};
    }
    void addSurfgrad(const GlslExpr& g) { lines_.push_back("surfGrad += " + g.text + ";"); }
    void assign(const GlslExpr& lhs, const GlslExpr& rhs) {
        lines_.push_back(lhs.text + " = " + rhs.text + ";");
    }
    // A call as a statement (a function that writes out arguments; SG_LAYER_RUN).
    template <class F, class... A>
    void run(const char* name, F&& f, const A&... args) {
        lines_.push_back(call(name, std::forward<F>(f), args...).text + ";");
    }

    // `type name = init;`.
    GlslExpr local(const char* type, const char* name, const GlslExpr& init) {
        lines_.push_back(std::string(type) + " " + name + " = " + init.text + ";");
        return {name};
    }

    // One statement (a block when there are several; the assembler may guard
    // it with an `if`), ending in a newline.
    std::string statement() const {
        if (lines_.size() == 1) return lines_[0] + "\n";
        std::string o = "{\n";
        for (const std::string& l : lines_) o += c_.indent + "    " + l + "\n";
        return o + c_.indent + "}\n";
    }

private:
    static std::string text(const GlslExpr& e) { return e.text; }
    const GlslLayerContext& c_;
    std::vector<std::string> lines_;
};

// A record layout's unpacked struct on the CPU: converts to the C++ build's
// struct of its unpacker (checked against the layout's type).
struct CpuRecord {
    const RecordLayout* layout;
    const glm::vec4* records; // the layer's first record
    template <class S>
    operator S() const {
        SG_ASSERT(*layout->unpackType == typeid(S), "a record unpacks to its layout's struct");
        S s;
        layout->unpackTo(records + layout->first, &s);
        return s;
    }
};

class CpuBinder {
public:
    CpuBinder(const CpuLayerContext& c, CpuShadeState& s, glm::vec3 nrm = glm::vec3(0.0f))
        : c_(c), s_(s), nrm_(nrm) {}

    const Layer& layer() const { return c_.layer(); }
    const MaterialPlan& plan() const { return c_.plan; }
    const CpuLayerContext& context() const { return c_; }

    sg::glsl::SgFrame& frame() { return s_.frame; }
    sg::glsl::SgUvFrame& uv() { return s_.uv[size_t(layer().uvSet)]; }
    sg::glsl::SgVolumeSpace& vol(Space sp) {
        return sp == Space::World ? s_.volWorld : s_.volObject;
    }
    glm::vec3& surfPos() { return s_.surfPos; }
    glm::vec3& surfOffset() { return s_.surfOffset; }
    glm::mat3& slopeCov() { return s_.slopeCov; }
    CpuRecord record(size_t layout = 0) const { return {&layer().kind->records[layout], c_.rec()}; }
    sg::glsl::sampler2D tex(int i) const { return c_.tex(i); }
    int constant(int v) const { return v; }
    int constant(int v, const char*) const { return v; }
    bool constant(bool v) const { return v; }
    glm::vec3 vertexNormal() const { return c_.in.normal; }
    glm::vec3 vertexNormalDx() const { return c_.in.dNdx; }
    glm::vec3 vertexNormalDy() const { return c_.in.dNdy; }
    float fragCoordX() const { return c_.in.fragCoord.x; }
    float fragCoordY() const { return c_.in.fragCoord.y; }
    glm::mat3 identity3() const { return glm::mat3(1.0f); }
    glm::vec3 relPos() const { return c_.in.relPos; }
    glm::vec3 objPos() const { return c_.in.objPos; }
    glm::mat3 normalMat() const { return c_.u.normalMat; }
    glm::mat3 model3() const { return c_.u.model3; }
    glm::mat3 modelInv3() const { return c_.u.modelInv3; }
    glm::vec3 resolvedNormal() const { return nrm_; }
    bool hasModifiers() const { return c_.pl.hasModifiers; }
    glm::vec2 uvSt() { return uv().st; }
    glm::vec2 uvDx() { return uv().dSTdx; }
    glm::vec2 uvDy() { return uv().dSTdy; }
    glm::mat2 identity2() const { return sg::glsl::sgModNoWarp(); }
    glm::vec4 modifierRecord(size_t i) const { return c_.u.records[size_t(c_.pl.modRecord) + i]; }
    sg::glsl::sampler2D modifierMask(size_t i) const {
        const int slot = c_.pl.modTex[i];
        return slot >= 0 ? c_.samplers[size_t(slot)] : sg::glsl::sampler2D{};
    }

    template <class T>
    T declare(const char*, const char*, const T& init) const {
        return init;
    }
    template <class F, class... A>
    decltype(auto) call(const char*, F&& f, A&&... args) const {
        return f(std::forward<A>(args)...);
    }
    void addSurfgrad(glm::vec3 g) { s_.surfGrad += g; }
    template <class T>
    T local(const char*, const char*, const T& init) const {
        return init;
    }
    template <class L, class R>
    void assign(L& lhs, const R& rhs) const {
        lhs = rhs;
    }
    template <class F, class... A>
    void run(const char*, F&& f, A&&... args) const {
        f(std::forward<A>(args)...);
    }

private:
    const CpuLayerContext& c_;
    CpuShadeState& s_;
    glm::vec3 nrm_;
};

// The C++ build of shared function `fn` as a callable (the CPU binder's).
#define SG_LAYER_FN(fn)                                                                            \
    [](auto&&... sgArgs) -> decltype(auto) {                                                       \
        return ::sg::glsl::fn(std::forward<decltype(sgArgs)>(sgArgs)...);                          \
    }

// The shared function `fn` called through binder `b`: GLSL writes its name,
// the CPU calls sg::glsl::fn (the C++ build of the same source).
#define SG_LAYER_CALL(b, fn, ...) (b).call(#fn, SG_LAYER_FN(fn), __VA_ARGS__)

// The same call as a statement of its own (a function writing out arguments).
#define SG_LAYER_RUN(b, fn, ...) (b).run(#fn, SG_LAYER_FN(fn), __VA_ARGS__)

// The kind's emitter from one generic lambda over a binder (no captures):
// its GLSL statement and its CPU call. constexpr, so a kind's `constexpr LayerEmitter kEmit =
// emitter(...)` is initialised before any registry lookup.
template <class F>
constexpr LayerEmitter emitter(F) {
    static_assert(std::is_empty_v<F>, "an emitter captures nothing");
    return LayerEmitter{
        [](const GlslLayerContext& c) {
            GlslBinder b(c);
            F{}(b);
            return b.statement();
        },
        [](const CpuLayerContext& c, CpuShadeState& s, glm::vec3 nrm) {
            CpuBinder b(c, s, nrm);
            F{}(b);
        },
    };
}

// ---------------------------------------------------------------------------
// Derivative-space modifiers (Loviscach 2008; layer_kind.h, section 4).

template <>
struct ModifierArgs<GlslBinder> {
    GlslExpr op, mask, st, dx, dy, jac;
};
template <>
struct ModifierArgs<CpuBinder> {
    glm::vec4 op{0.0f};
    sg::glsl::sampler2D mask{};
    glm::vec2 st{0.0f}, dx{0.0f}, dy{0.0f};
    glm::mat2 jac{1.0f};
};

// A modifier's statement from one generic lambda (b, hd, args).
template <class F>
constexpr ModifierEmitter modifierEmitter(F) {
    static_assert(std::is_empty_v<F>, "an emitter captures nothing");
    return ModifierEmitter{
        [](GlslBinder& b, GlslExpr& hd, const ModifierArgs<GlslBinder>& in) { F{}(b, hd, in); },
        [](CpuBinder& b, sg::glsl::SgHeightDeriv& hd, const ModifierArgs<CpuBinder>& in) {
            F{}(b, hd, in);
        },
    };
}

// A lookup warp from one generic lambda (b, args).
template <class F>
constexpr ModifierWarp modifierWarp(F) {
    static_assert(std::is_empty_v<F>, "an emitter captures nothing");
    return ModifierWarp{
        [](GlslBinder& b, ModifierArgs<GlslBinder>& in) { F{}(b, in); },
        [](CpuBinder& b, ModifierArgs<CpuBinder>& in) { F{}(b, in); },
    };
}

inline void applyModifier(GlslBinder& b, const ModifierKind& k, GlslExpr& hd,
                          const ModifierArgs<GlslBinder>& in) {
    k.emit.glsl(b, hd, in);
}
inline void applyModifier(CpuBinder& b, const ModifierKind& k, sg::glsl::SgHeightDeriv& hd,
                          const ModifierArgs<CpuBinder>& in) {
    k.emit.cpu(b, hd, in);
}
inline void applyWarp(GlslBinder& b, const ModifierKind& k, ModifierArgs<GlslBinder>& in) {
    k.warp.glsl(b, in);
}
inline void applyWarp(CpuBinder& b, const ModifierKind& k, ModifierArgs<CpuBinder>& in) {
    k.warp.cpu(b, in);
}

// The block of a layer with modifiers: its parameters `p` (type
// paramsType, record 0), the lookup (the UV frame's, or the first
// modifier's warp), the sample as height and derivative
// (sample(b, p, st, dx, dy): an SgHeightDeriv), one statement per modifier
// in order (only the kinds used are compiled in; nothing branches on a
// uniform), and surfgrad(b, p, hd) added to surfGrad.
template <class B, class Sample, class Surfgrad>
void addDerivModSurfgrad(B& b, const char* paramsType, Sample sample, Surfgrad surfgrad) {
    const Layer& L = b.layer();
    auto p = b.local(paramsType, "p", b.record());
    ModifierArgs<B> in;
    const ModifierKind& first = *L.modifiers[0].kind;
    if (first.warpsLookup) {
        in.op = b.modifierRecord(0);
        applyWarp(b, first, in);
    } else {
        in.st = b.local("vec2", "st", b.uvSt());
        in.dx = b.local("vec2", "dx", b.uvDx());
        in.dy = b.local("vec2", "dy", b.uvDy());
        in.jac = b.identity2();
    }
    auto hd = b.local("SgHeightDeriv", "hd", sample(b, p, in.st, in.dx, in.dy));
    for (size_t i = 0; i < L.modifiers.size(); ++i) {
        in.op = b.modifierRecord(i);
        in.mask = b.modifierMask(i);
        applyModifier(b, *L.modifiers[i].kind, hd, in);
    }
    b.addSurfgrad(surfgrad(b, p, hd));
}

} // namespace sg::render
