// Derivative-space modifiers as units (deriv_mods.glsl: Loviscach 2008 on
// the height h and derivative d of a layer, before its surface gradient):
// one ModifierKind per modifier, with its scene fields, its record and its
// one emitter (the GLSL statement and the CPU call, layer_emit.h). The layer
// kinds that take modifiers (uv_normal, deriv_map) call addDerivModSurfgrad
// with their sampling and surface-gradient steps.
#include "layer_emit.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using detail::kHuge;
using detail::SceneNode;
using detail::SceneReader;

// Records: one vec4 per modifier, (SG_MOD_* id, a, b, 0), modulate
// (id, mask channel, gain, 0): deriv_mods.glsl reads op.y, op.z.
glm::vec4 packAB(const Modifier& m) {
    return {float(m.kind->id), m.a, m.b, 0.0f};
}

// SCALE (alpha): h' = alpha h, d' = alpha d.
const ModifierKind kScale{
    .name = "scale",
    .id = SG_MOD_SCALE,
    .sigCode = 's',
    .fields = {"alpha"},
    .doc = "h, d times alpha",
    .parse = [](const SceneNode& m, Modifier& mod,
                const SceneReader&) { mod.a = m.num("alpha", 1.0, -kHuge, kHuge); },
    .pack = packAB,
    .emit = modifierEmitter([](auto& b, auto& hd, const auto& in) {
        b.assign(hd, SG_LAYER_CALL(b, sgModScale, hd, in.op));
    }),
};

// CURVE (P, H): f'(h) = 1 / (1 + P (h - H)^2).
const ModifierKind kCurve{
    .name = "curve",
    .id = SG_MOD_CURVE,
    .sigCode = 'c',
    .fields = {"boost", "center"},
    .doc = "slope curve f'(h) = 1 / (1 + P (h - H)^2)",
    .parse =
        [](const SceneNode& m, Modifier& mod, const SceneReader&) {
            mod.a = m.num("boost", 1.0, 0.0, kHuge);
            mod.b = m.num("center", 0.0, -kHuge, kHuge);
        },
    .pack = packAB,
    .emit = modifierEmitter([](auto& b, auto& hd, const auto& in) {
        b.assign(hd, SG_LAYER_CALL(b, sgModCurve, hd, in.op));
    }),
};

// MODULATE (mask channel, gain): product rule with the mask's derivative,
// carried through the lookup warp's Jacobian (the identity without DEFORM).
const ModifierKind kModulate{
    .name = "modulate",
    .id = SG_MOD_MODULATE,
    .sigCode = 'm',
    .fields = {"mask", "channel", "gain"},
    .doc = "product with a mask (product rule)",
    .parse =
        [](const SceneNode& m, Modifier& mod, const SceneReader& reader) {
            if (!m.has("mask")) m.fail("missing \"mask\" (the texture to modulate by)");
            mod.mask = reader.texture(m.child("mask"), Wrap::Repeat);
            mod.channel = m.choice("channel", 0, {"r", "g", "b", "a"});
            mod.a = m.num("gain", 1.0, -kHuge, kHuge);
        },
    .pack = [](const Modifier& m) -> glm::vec4 {
        return {float(m.kind->id), float(m.channel), m.a, 0.0f};
    },
    .emit = modifierEmitter([](auto& b, auto& hd, const auto& in) {
        b.assign(hd,
                 SG_LAYER_CALL(b, sgModModulate, hd, in.op, in.mask, in.st, in.dx, in.dy, in.jac));
    }),
};

// DEFORM (A, B): the lookup warps to (s, t + A sin(B s)); d' = J^T d.
const ModifierKind kDeform{
    .name = "deform",
    .id = SG_MOD_DEFORM,
    .sigCode = 'd',
    .fields = {"amplitude", "frequency"},
    .doc = "warped lookup (s, t + A sin(B s)), d' = J^T d",
    .warpsLookup = true,
    .parse =
        [](const SceneNode& m, Modifier& mod, const SceneReader&) {
            mod.a = m.num("amplitude", 0.02, -kHuge, kHuge);
            mod.b = m.num("frequency", 20.0, -kHuge, kHuge);
        },
    .pack = packAB,
    .warp = modifierWarp([](auto& b, auto& in) {
        in.jac = b.declare("mat2", "jac", glm::mat2(1.0f));
        in.st = b.local("vec2", "st", SG_LAYER_CALL(b, sgModWarp, in.op, b.uvSt(), in.jac));
        in.dx = b.local("vec2", "dx", SG_LAYER_CALL(b, sgModWarpDeriv, in.jac, b.uvDx()));
        in.dy = b.local("vec2", "dy", SG_LAYER_CALL(b, sgModWarpDeriv, in.jac, b.uvDy()));
    }),
    .emit = modifierEmitter([](auto& b, auto& hd, const auto& in) {
        b.assign(hd, SG_LAYER_CALL(b, sgModDeform, hd, in.jac));
    }),
};

void parseModifiers(const SceneNode& n, const char* key, Layer& L, const SceneReader& reader) {
    if (!n.has(key)) return;
    n.requireArray(key, size_t(kMaxModifiers));
    SceneNode arr = n.child(key);
    std::vector<const char*> names;
    std::string list;
    const auto& kinds = modifierKinds();
    for (size_t k = 0; k < kinds.size(); ++k) {
        names.push_back(kinds[k]->name);
        list += std::string(k == 0 ? "" : k + 1 == kinds.size() ? " or " : ", ") + kinds[k]->name;
    }
    for (size_t i = 0; i < arr.value().size(); ++i) {
        SceneNode m = arr.item(i);
        m.requireObject();
        int k = m.choice("type", -1, names);
        if (k < 0) m.fail("missing \"type\" (" + list + ")");
        Modifier mod;
        mod.kind = kinds[size_t(k)];
        std::vector<const char*> allowed = {"type"};
        allowed.insert(allowed.end(), mod.kind->fields.begin(), mod.kind->fields.end());
        m.allowOnly(allowed);
        if (mod.kind->warpsLookup && i != 0) {
            m.fail(std::string("a ") + mod.kind->name +
                   " modifier warps the lookup and must come first");
        }
        mod.kind->parse(m, mod, reader);
        L.modifiers.push_back(std::move(mod));
    }
}

} // namespace

const std::vector<const ModifierKind*>& modifierKinds() {
    static const std::vector<const ModifierKind*> kinds = {&kScale, &kCurve, &kModulate, &kDeform};
    return kinds;
}

ParamSpec param::modifiers() {
    return custom("modifiers", parseModifiers,
                  "derivative-space modifiers, at most 4 (scale, curve, modulate, deform)");
}

} // namespace sg::render
