// Derivative-space modifiers as units (deriv_mods.glsl: Loviscach 2008 on
// the height h and derivative d of a layer, before its surface gradient):
// one ModifierKind per modifier, with its scene fields, its record, the
// GLSL statement the assembler emits and the CPU call beside it. The layer
// kinds that take modifiers (uv_normal, deriv_map) call derivModBlock /
// derivModCpu with their sampling and surface-gradient steps.
#include "layer_kind.h"

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
    .glsl = [](const ModifierGlslInputs& in) { return "hd = sgModScale(hd, " + in.op + ");"; },
    .cpu = [](const G::SgHeightDeriv& hd, const glm::vec4& op,
              const ModifierCpuInputs&) { return G::sgModScale(hd, op); },
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
    .glsl = [](const ModifierGlslInputs& in) { return "hd = sgModCurve(hd, " + in.op + ");"; },
    .cpu = [](const G::SgHeightDeriv& hd, const glm::vec4& op,
              const ModifierCpuInputs&) { return G::sgModCurve(hd, op); },
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
    .glsl =
        [](const ModifierGlslInputs& in) {
            return "hd = sgModModulate(hd, " + in.op + ", " + in.mask + ", st, dx, dy, " + in.jac +
                   ");";
        },
    .cpu =
        [](const G::SgHeightDeriv& hd, const glm::vec4& op, const ModifierCpuInputs& in) {
            return G::sgModModulate(hd, op, in.mask, in.st, in.dx, in.dy, in.jac);
        },
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
    .glslWarp =
        [](const std::string& op, const std::string& uv, const std::string& in) {
            return in + "mat2 jac;\n" + in + "vec2 st = sgModWarp(" + op + ", " + uv +
                   ".st, jac);\n" + in + "vec2 dx = jac * " + uv + ".dSTdx;\n" + in +
                   "vec2 dy = jac * " + uv + ".dSTdy;\n";
        },
    .warpCpu = [](const glm::vec4& op, glm::vec2 st,
                  glm::mat2& jac) { return G::sgModWarp(op, st, jac); },
    .glsl = [](const ModifierGlslInputs&) { return std::string("hd = sgModDeform(hd, jac);"); },
    .cpu = [](const G::SgHeightDeriv& hd, const glm::vec4&,
              const ModifierCpuInputs& in) { return G::sgModDeform(hd, in.jac); },
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

std::string opRecord(const PlanLayer& pl, size_t i) {
    return "uLayerData[" + std::to_string(pl.modRecord + int(i)) + "]";
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

// The sample as height and derivative, one call per modifier in order (only
// the kinds used are compiled in; nothing branches on a uniform), and the
// surface gradient.
std::string derivModBlock(const GlslLayerContext& c, const DerivModTarget& t) {
    const Layer& L = c.layer();
    const std::string uv = c.uv(), in = c.indent + "    ";
    std::string o = "{\n" + in + t.glslParams(c) + "\n";
    const ModifierKind* first = L.modifiers[0].kind;
    if (first->warpsLookup) {
        o += first->glslWarp(opRecord(c.pl, 0), uv, in);
    } else {
        o += in + "vec2 st = " + uv + ".st;\n" + in + "vec2 dx = " + uv + ".dSTdx;\n" + in +
             "vec2 dy = " + uv + ".dSTdy;\n";
    }
    o += in + "SgHeightDeriv hd = " + t.glslSample + "(" + c.tex(0) + ", st, dx, dy, p);\n";
    for (size_t i = 0; i < L.modifiers.size(); ++i) {
        int mask = c.pl.modTex[i];
        ModifierGlslInputs mi{opRecord(c.pl, i), mask >= 0 ? "uTex" + std::to_string(mask) : "",
                              first->warpsLookup ? "jac" : "mat2(1.0f)"};
        o += in + L.modifiers[i].kind->glsl(mi) + "\n";
    }
    o += in + "surfGrad += " + t.glslSurfgrad(c) + ";\n";
    return o + c.indent + "}\n";
}

glm::vec3 derivModCpu(const CpuLayerContext& c, const CpuShadeState& s, const DerivModTarget& t) {
    const Layer& L = c.layer();
    const glm::vec4* op = &c.u.records[size_t(c.pl.modRecord)];
    const G::SgUvFrame& f = c.uv(s);
    ModifierCpuInputs in;
    in.st = f.st;
    in.dx = f.dSTdx;
    in.dy = f.dSTdy;
    if (L.modifiers[0].kind->warpsLookup) {
        in.st = L.modifiers[0].kind->warpCpu(op[0], f.st, in.jac);
        in.dx = in.jac * f.dSTdx;
        in.dy = in.jac * f.dSTdy;
    }
    G::SgHeightDeriv hd = t.sampleCpu(c, in.st, in.dx, in.dy);
    for (size_t i = 0; i < L.modifiers.size(); ++i) {
        in.mask = c.pl.modTex[i] >= 0 ? c.samplers[size_t(c.pl.modTex[i])] : G::sampler2D{};
        hd = L.modifiers[i].kind->cpu(hd, op[i], in);
    }
    return t.surfgradCpu(c, s, hd);
}

} // namespace sg::render
