// Shader assembly with effects on demand, and the CPU twin of the assembled
// program.
//
// A MaterialPlan (material_plan.cpp) lists a material's enabled layers in
// groups (group 0, then one group per post_resolve entry: Mikkelsen 2019,
// section 3), with the uniform records and texture slots each layer reads.
// From one plan:
//   - fragmentBody() writes the GLSL main(): the prologue (listing 16), one
//     statement per layer (its kind's, layer_kind.h), a resolve per group
//     (listing 1) and a re-prologue between groups (sections 2.11 and 3);
//     only the files of the kinds the plan uses are #included;
//   - shadePixelCpu() makes the same calls, in the same order, through the
//     C++ build of the same files (each kind's CPU call beside its GLSL
//     statement in shaders/sg/render/layer_<kind>.cpp).
// The two are written side by side below, step by step.
#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

#include "layer_kind.h"
#include "render_internal.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::render {

namespace {

uint32_t groupUvMask(const std::vector<PlanLayer>& g) {
    uint32_t m = 0;
    for (const auto& pl : g)
        if (pl.layer->kind->readsUv) m |= 1u << pl.layer->uvSet;
    return m;
}

// UV sets whose frames the prologue builds: those of group 0, set 0 always
// (for the tangent and uv outputs), and any other set the plan reads.
uint32_t prologueUvMask(const MaterialPlan& plan) {
    return groupUvMask(plan.groups[0]) | (plan.uvCount > 0 ? 1u : 0u) | plan.uvUsedMask;
}

// The group's layers in emission order: one statement per layer in order,
// then each batched kind (registry order) with its layers in order.
struct GroupOrder {
    std::vector<const PlanLayer*> single;
    std::vector<std::pair<const LayerKind*, std::vector<const PlanLayer*>>> batches;
};

// A layer of the plan moves the surface (LayerKind::movesSurface): main()
// holds surfOffset and surfPos and samples the base colour after group 0's
// layers.
bool movesSurface(const MaterialPlan& plan) {
    return planMovesSurface(plan);
}

// The layer whose re-prologue group g uses: the last one before the group
// with a `reprologue` (nullptr: the default re-prologue).
const PlanLayer* reprologueLayer(const MaterialPlan& plan, size_t g) {
    const PlanLayer* last = nullptr;
    for (size_t h = 0; h < g; ++h)
        for (const PlanLayer& pl : plan.groups[h])
            if (pl.layer->kind->reprologue) last = &pl;
    return last;
}

GroupOrder groupOrder(const MaterialPlan& plan, const std::vector<PlanLayer>& group) {
    GroupOrder o;
    for (const PlanLayer& pl : group)
        if (!pl.layer->kind->batch) o.single.push_back(&pl);
    for (const LayerKind* k : plan.kinds) {
        if (!k->batch) continue;
        std::vector<const PlanLayer*> v;
        for (const PlanLayer& pl : group)
            if (pl.layer->kind == k) v.push_back(&pl);
        if (!v.empty()) o.batches.emplace_back(k, std::move(v));
    }
    return o;
}

// ---------------------------------------------------------------------------
// GLSL

std::string tex(int slot) {
    return "uTex" + std::to_string(slot);
}
std::string uvVar(int set) {
    return "uv" + std::to_string(set);
}

} // namespace

std::vector<std::string> layerGlslFiles(const MaterialPlan& plan) {
    std::vector<std::string> files;
    for (const auto& g : plan.groups)
        for (const auto& pl : g) {
            const LayerKind& k = *pl.layer->kind;
            std::string f = pl.hasModifiers ? k.modifiers->glslFile
                            : k.glslFileOf  ? k.glslFileOf(*pl.layer)
                                            : k.glslFile;
            if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
        }
    if (plan.antialias) files.push_back("sg/render/antialias.glsl");
    return files;
}

namespace {

// Includes, uniforms and the kinds' program-level declarations.
void emitDeclarations(const MaterialPlan& plan, std::ostringstream& o) {
    o << "// surfgrad assembled fragment program (render/src/plan.cpp).\n"
      << "// Effect signature: " << plan.signature << "\n"
      << "// Only the layer kinds this material uses are included below.\n"
      << "#include \"sg/render/surface_fs.glsl\"\n";
    for (const auto& f : layerGlslFiles(plan)) o << "#include \"" << f << "\"\n";
    for (size_t i = 0; i < plan.textureKeys.size(); ++i) {
        o << "uniform sampler2D uTex" << i << "; // "
          << (plan.textureKeys[i].empty() ? "(none)" : plan.textureKeys[i]) << "\n";
    }
    for (const LayerKind* k : plan.kinds)
        if (k->programDeclarations) o << k->programDeclarations(plan);
    if (plan.uber) o << "uniform float uLayerOn[" << std::max(plan.uberFlagCount, 1) << "];\n";
    if (plan.adaptive) {
        o << "#define SG_AOV_PATCH 8\n"
          << "flat in vec4 vPatchAov; // patch AOV (sg/patch/patch_tes.glsl)\n";
    }
    if (plan.displacementUvSet >= 0) {
        o << "in vec3 vRelPosLit; // displaced position, lit (vRelPos: undisplaced, the frame's; "
             "section 2.5)\n";
    }
}

// The base colour: after the prologue, or after group 0's layers when a
// layer moves the surface (they may correct the UV coordinates).
void emitBaseColor(const MaterialPlan& plan, std::ostringstream& o) {
    o << "    vec3 baseColor = uBaseColor;\n";
    if (plan.baseColorTex >= 0) {
        std::string uv = uvVar(plan.baseColorUvSet);
        o << "    baseColor *= textureGrad(" << tex(plan.baseColorTex) << ", " << uv << ".st, "
          << uv << ".dSTdx, " << uv << ".dSTdy).xyz; // base colour map (linear)\n";
    }
}

// main() up to the first layer: prologue, UV frames, volume domains, base colour.
void emitPrologue(const MaterialPlan& plan, std::ostringstream& o) {
    o << "\nvoid main() {\n"
      << "    // Prologue (Mikkelsen 2019, listing 16): derivatives of the camera-relative "
         "position.\n"
      << "    vec3 dPdx = SG_DFDX(vRelPos);\n"
      << "    vec3 dPdy = SG_DFDY(vRelPos);\n"
      << "    SgFrame frame = sgPrologue(vNormal, dPdx, dPdy, gl_FrontFacing, uBfaceMode);\n"
      << "    vec3 baseNormal = frame.resolveSign * frame.nrmBase; // as displayed (flip: "
         "negated)\n";
    const uint32_t uvMask = prologueUvMask(plan);
    for (int k = 0; k < plan.uvCount; ++k) {
        if (!(uvMask >> k & 1u)) continue;
        std::string v = "vUv" + std::to_string(k);
        o << "    vec2 dUv" << k << "dx = SG_DFDX(" << v << ");\n"
          << "    vec2 dUv" << k << "dy = SG_DFDY(" << v << ");\n";
        if (plan.vertexTangentMask >> k & 1u) {
            o << "    SgUvFrame uv" << k << " = sgUvFrameVertex(" << v << ", dUv" << k << "dx, dUv"
              << k << "dy, vNormal, vTangent" << k << ");\n";
        } else {
            o << "    SgUvFrame uv" << k << " = sgUvFramePixel(frame, " << v << ", dUv" << k
              << "dx, dUv" << k << "dy);\n";
        }
    }
    if (plan.usesWorldVolume) {
        // Camera-relative: the layers add the camera's part, packed per layer
        // (SgVolumeSpace, sg/render/common.glsl).
        o << "    SgVolumeSpace volWorld = sgVolumeSpace(frame, vRelPos, mat3(1.0), "
             "mat3(1.0));\n";
    }
    if (plan.usesObjectVolume) {
        o << "    SgVolumeSpace volObject = sgVolumeSpaceDeriv(vObjPos, SG_DFDX(vObjPos), "
             "SG_DFDY(vObjPos), uModel3, uModelInv3);\n";
    }
    if (!movesSurface(plan)) emitBaseColor(plan, o);
    o << "    vec3 surfGrad = vec3(0.0);\n";
    if (plan.antialias) {
        o << "    mat3 slopeCov = mat3(0.0); // the layers' slope covariances "
             "(sg/render/antialias.glsl)\n";
    }
    if (movesSurface(plan)) {
        o << "    vec3 surfOffset = vec3(0.0); // the virtual surface (parallax, section 3)\n"
          << "    vec3 surfPos = vRelPos; // the frame's surface: the virtual one after a "
             "re-prologue\n";
    }
}

// One group: the re-prologue (groups after the first), the layers, the resolve.
void emitGroup(const MaterialPlan& plan, size_t g, std::ostringstream& o) {
    std::string indent = "    ";
    if (g > 0) {
        o << "    // Post-resolve group " << g
          << " (section 3): the resolved normal is the new base.\n";
        if (plan.uber) {
            o << "    if (uLayerOn[" << plan.groupUberIndex[g] << "] > 0.5) {\n";
            indent = "        ";
        }
        if (const PlanLayer* rp = reprologueLayer(plan, g)) {
            // The virtual surface of a layer that moved it (section 3).
            GlslLayerContext c{plan, *rp, indent};
            if (plan.uber) {
                o << indent << "if (uLayerOn[" << rp->uberIndex << "] > 0.5) ";
                o << rp->layer->kind->reprologue.glsl(c);
                o << indent << "else frame = sgReprologue(frame, nrm, frame.dPdx, frame.dPdy);\n";
            } else {
                o << indent << rp->layer->kind->reprologue.glsl(c);
            }
        } else {
            o << indent << "frame = sgReprologue(frame, nrm, frame.dPdx, frame.dPdy);\n";
        }
        uint32_t m = groupUvMask(plan.groups[g]);
        for (int k = 0; k < plan.uvCount; ++k) {
            if (m >> k & 1u) {
                o << indent << "uv" << k << " = sgUvFramePixel(frame, uv" << k << ".st, uv" << k
                  << ".dSTdx, uv" << k << ".dSTdy);\n";
            }
        }
        o << indent << "surfGrad = vec3(0.0);\n";
    }
    GroupOrder order = groupOrder(plan, plan.groups[g]);
    for (const PlanLayer* pl : order.single) {
        o << indent << "// " << pl->layer->kind->name << " (" << pl->layer->fieldPath << ")\n";
        if (plan.uber) {
            o << indent << "if (uLayerOn[" << pl->uberIndex << "] > 0.5) ";
        } else {
            o << indent;
        }
        o << pl->layer->kind->emit.glsl(GlslLayerContext{plan, *pl, indent});
    }
    for (const auto& [kind, layers] : order.batches)
        o << kind->batch->groupStatements(plan, layers, indent);
    if (g == 0) {
        if (movesSurface(plan)) emitBaseColor(plan, o);
        o << "    vec3 nrm = sgResolve(frame, surfGrad); // listing 1\n"
          << "    vec3 surfGradOut = surfGrad;\n";
    } else {
        o << indent << "nrm = sgResolve(frame, surfGrad);\n";
        if (plan.uber) o << "    }\n";
    }
}

// Lights and the output variable.
void emitShading(const MaterialPlan& plan, std::ostringstream& o) {
    std::string roughness = "uRoughness";
    if (plan.antialias) {
        o << "    float roughness = sgAaRoughness(uRoughness, slopeCov); // lobe widened by the "
             "bumps\n";
        roughness = "roughness";
    }
    // The lit position: the displaced one (section 2.5), moved to the
    // virtual surface when a layer moved it (section 3: the corrected
    // position serves shading and lighting, point lights and the view vector).
    std::string lit = plan.displacementUvSet >= 0 ? "vRelPosLit" : "vRelPos";
    if (movesSurface(plan)) lit = "(" + lit + " + surfOffset)";
    o << "    vec3 color = sgShadeAmbient(nrm, uAmbient, baseColor);\n"
      << "    for (int i = 0; i < SG_LIGHT_COUNT; ++i) {\n"
      << "        color += sgShadeLight(nrm, " << lit
      << ", uLights[2 * i], uLights[2 * i + 1], "
         "baseColor, "
      << roughness << ");\n"
      << "    }\n";
    if (plan.uvCount > 0) {
        o << "    outValue = sgAovValue(uAov, color, nrm, surfGradOut, uv0.vT, uv0.vB, baseNormal, "
             "vUv0,\n";
    } else {
        o << "    outValue = sgAovValue(uAov, color, nrm, surfGradOut, vec3(0.0), vec3(0.0), "
             "baseNormal, vec2(0.0),\n";
    }
    o << "                          float(SG_PRIMITIVE_ID) + 1.0 + uPrimBase);\n";
    if (plan.adaptive) o << "    if (uAov == SG_AOV_PATCH) outValue = vPatchAov;\n";
    o << "}\n";
}

} // namespace

std::string fragmentBody(const MaterialPlan& plan) {
    std::ostringstream o;
    emitDeclarations(plan, o);
    emitPrologue(plan, o);
    for (size_t g = 0; g < plan.groups.size(); ++g) emitGroup(plan, g, o);
    emitShading(plan, o);
    return o.str();
}

namespace {

bool isIdentStart(char c) {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool isIdent(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// Effects on demand, at the level of functions: the shared library files
// hold whole families of functions (e.g. every listing of the paper in
// sg/surfgrad.glsl); a program keeps only those main() reaches. Shared
// functions are recognised by their `SG_FN type name(` opening line;
// removed ones are replaced by as many empty lines, so #line numbers stay
// right. Overloads are kept or dropped together (by name).
std::string stripUnreachableFunctions(const std::string& text) {
    std::vector<std::string> lines;
    {
        std::istringstream in(text);
        std::string l;
        while (std::getline(in, l)) lines.push_back(l);
    }
    struct Fn {
        std::string name;
        size_t first, last; // line range
    };
    std::vector<Fn> fns;
    std::vector<char> inFn(lines.size(), 0);
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string& l = lines[i];
        if (l.rfind("SG_FN ", 0) != 0) continue;
        size_t paren = l.find('(');
        if (paren == std::string::npos) continue;
        size_t e = paren;
        while (e > 0 && l[e - 1] == ' ') --e;
        size_t b = e;
        while (b > 0 && isIdent(l[b - 1])) --b;
        Fn f{l.substr(b, e - b), i, i};
        // The body ends where the braces opened after the name balance.
        int depth = 0;
        bool opened = false;
        size_t j = i;
        for (; j < lines.size(); ++j) {
            for (char c : lines[j]) {
                if (c == '{') {
                    ++depth;
                    opened = true;
                } else if (c == '}') {
                    --depth;
                }
            }
            if (opened && depth == 0) break;
        }
        if (j == lines.size()) continue; // unbalanced: leave the file alone
        f.last = j;
        for (size_t k = f.first; k <= f.last; ++k) inFn[k] = 1;
        fns.push_back(f);
        i = j;
    }
    auto tokens = [&](size_t from, size_t to, std::set<std::string>& out) {
        for (size_t k = from; k <= to; ++k) {
            const std::string& l = lines[k];
            for (size_t p = 0; p < l.size();) {
                if (l.compare(p, 2, "//") == 0) break;
                if (isIdentStart(l[p]) && (p == 0 || !isIdent(l[p - 1]))) {
                    size_t q = p;
                    while (q < l.size() && isIdent(l[q])) ++q;
                    out.insert(l.substr(p, q - p));
                    p = q;
                } else {
                    ++p;
                }
            }
        }
    };
    // Roots: everything outside shared functions (main, declarations).
    std::set<std::string> used;
    for (size_t k = 0; k < lines.size(); ++k) {
        if (!inFn[k]) tokens(k, k, used);
    }
    std::set<std::string> kept;
    for (bool changed = true; changed;) {
        changed = false;
        for (const Fn& f : fns) {
            if (kept.count(f.name) || !used.count(f.name)) continue;
            kept.insert(f.name);
            for (const Fn& g : fns) {
                if (g.name == f.name) tokens(g.first, g.last, used);
            }
            changed = true;
        }
    }
    std::string out;
    out.reserve(text.size());
    std::vector<char> drop(lines.size(), 0);
    for (const Fn& f : fns) {
        if (!kept.count(f.name)) {
            for (size_t k = f.first; k <= f.last; ++k) drop[k] = 1;
            // ... and the comment block documenting it, directly above.
            for (size_t k = f.first; k > 0; --k) {
                const std::string& l = lines[k - 1];
                size_t p = l.find_first_not_of(" \t");
                if (p == std::string::npos || l.compare(p, 2, "//") != 0) break;
                drop[k - 1] = 1;
            }
        }
    }
    for (size_t k = 0; k < lines.size(); ++k) {
        if (!drop[k]) out += lines[k];
        out += '\n';
    }
    return out;
}

} // namespace

ProgramSource assembleProgram(const MaterialPlan& plan) {
    std::vector<std::string> defs = {"SG_UV_COUNT " + std::to_string(plan.uvCount)};
    for (int k = 0; k < kMaxUvSets; ++k) {
        defs.push_back("SG_VTX_TANGENT_" + std::to_string(k) + " " +
                       std::to_string((plan.vertexTangentMask >> k) & 1u));
    }
    std::vector<std::string> fdefs = defs;
    fdefs.push_back("SG_LIGHT_COUNT " + std::to_string(plan.lightCount));
    fdefs.push_back("SG_LAYER_RECORDS " + std::to_string(std::max(plan.recordCount, 1)));
    for (const LayerKind* k : plan.kinds)
        if (k->programDefines) k->programDefines(plan, fdefs);
    auto f = sg::shaders::assemble(fragmentBody(plan), "(assembled fragment program)", fdefs);
    if (plan.adaptive) {
        // Patches carry UV sets and the "limit" tangents of the sets in
        // vertexTangentMask (the evaluation stage writes vUvk and vTangentk
        // under the same SG_VTX_TANGENT_k as the fragment program reads).
        const char* pvs = sg::shaders::find("sg/patch/patch_vs.glsl");
        const char* tes = sg::shaders::find("sg/patch/patch_tes.glsl");
        SG_ASSERT(pvs && tes, "the patch stages are embedded");
        auto v = sg::shaders::assemble(pvs, "sg/patch/patch_vs.glsl");
        std::vector<std::string> edefs;
        if (plan.uvCount > 0) edefs.push_back("SG_UV_COUNT " + std::to_string(plan.uvCount));
        for (int k = 0; k < kMaxUvSets; ++k) {
            if ((plan.vertexTangentMask >> k) & 1u)
                edefs.push_back("SG_VTX_TANGENT_" + std::to_string(k) + " 1");
        }
        if (plan.displacementUvSet >= 0) {
            edefs.push_back("SG_DISPLACEMENT 1");
            edefs.push_back("SG_DISP_UV_SET " + std::to_string(plan.displacementUvSet));
        }
        auto e = sg::shaders::assemble(tes, "sg/patch/patch_tes.glsl", edefs);
        return ProgramSource{v.text, stripUnreachableFunctions(f.text), v.files, f.files, e.text,
                             e.files};
    }
    const char* vs = sg::shaders::find("sg/render/surface_vs.glsl");
    SG_ASSERT(vs, "the vertex stage is embedded");
    auto v = sg::shaders::assemble(vs, "sg/render/surface_vs.glsl", defs);
    return ProgramSource{v.text, stripUnreachableFunctions(f.text), v.files, f.files, {}, {}};
}

sg::shaders::Assembled assemblePatchControl(int pointsPerPatch) {
    SG_EXPECTS(pointsPerPatch == 16 || pointsPerPatch == 20, "regular or Gregory-basis patches");
    const char* tcs = sg::shaders::find("sg/patch/patch_tcs.glsl");
    SG_ASSERT(tcs, "the patch stages are embedded");
    return sg::shaders::assemble(tcs, "sg/patch/patch_tcs.glsl",
                                 {"SG_PATCH_POINTS " + std::to_string(pointsPerPatch)});
}

// ---------------------------------------------------------------------------
// The CPU twin of fragmentBody(): same calls, same order.

namespace detail {

namespace {

namespace G = sg::glsl;

struct CpuShader {
    const MaterialPlan& plan;
    const DrawUniforms& u;
    const std::vector<G::sampler2D>& smp;
    const std::vector<std::any>& kindData; // planKindCpuData
    const PixelInputs& in;

    bool on(const PlanLayer& pl) const {
        return !plan.uber || u.uberFlags[size_t(pl.uberIndex)] > 0.5f;
    }
    // The layer's kind's entry of kindData (nullptr: none).
    const std::any* dataOf(const PlanLayer& pl) const {
        for (size_t i = 0; i < plan.kindPlans.size(); ++i)
            if (plan.kindPlans[i].kind == pl.layer->kind) return &kindData[i];
        return nullptr;
    }
    void layer(const PlanLayer& pl, CpuShadeState& s) const {
        if (on(pl))
            pl.layer->kind->emit.cpu(CpuLayerContext{plan, pl, u, smp, dataOf(pl), in}, s,
                                     glm::vec3(0.0f));
    }

    // emitPrologue()
    CpuShadeState prologue() const {
        CpuShadeState s;
        s.frame = G::sgPrologue(in.normal, in.dPdx, in.dPdy, in.frontFacing, u.bfaceMode);
        s.surfPos = in.relPos;
        const uint32_t uvMask = prologueUvMask(plan);
        for (int k = 0; k < plan.uvCount; ++k) {
            if (!(uvMask >> k & 1u)) continue;
            size_t kk = size_t(k);
            s.uv[kk] = (plan.vertexTangentMask >> k & 1u)
                           ? G::sgUvFrameVertex(in.uv[kk], in.dUVdx[kk], in.dUVdy[kk], in.normal,
                                                in.tangent[kk])
                           : G::sgUvFramePixel(s.frame, in.uv[kk], in.dUVdx[kk], in.dUVdy[kk]);
        }
        if (plan.usesWorldVolume)
            s.volWorld = G::sgVolumeSpace(s.frame, in.relPos, glm::mat3(1.0f), glm::mat3(1.0f));
        if (plan.usesObjectVolume)
            s.volObject =
                G::sgVolumeSpaceDeriv(in.objPos, in.dObjdx, in.dObjdy, u.model3, u.modelInv3);
        return s;
    }

    glm::vec3 baseColor(const CpuShadeState& s) const {
        glm::vec3 c = u.baseColor;
        if (plan.baseColorTex >= 0) {
            const G::SgUvFrame& f = s.uv[size_t(plan.baseColorUvSet)];
            c *= glm::vec3(G::textureGrad(smp[size_t(plan.baseColorTex)], f.st, f.dSTdx, f.dSTdy));
        }
        return c;
    }

    // emitGroup(): layers in the GLSL's order, then the resolve.
    glm::vec3 group(size_t g, CpuShadeState& s, glm::vec3 nrm,
                    glm::vec3* lateBaseColor = nullptr) const {
        if (g > 0) {
            const PlanLayer* rp = reprologueLayer(plan, g);
            if (rp && on(*rp))
                rp->layer->kind->reprologue.cpu(CpuLayerContext{plan, *rp, u, smp, dataOf(*rp), in},
                                                s, nrm);
            else
                s.frame = G::sgReprologue(s.frame, nrm, s.frame.dPdx, s.frame.dPdy);
            uint32_t m = groupUvMask(plan.groups[g]);
            for (int k = 0; k < plan.uvCount; ++k) {
                size_t kk = size_t(k);
                if (m >> k & 1u)
                    s.uv[kk] =
                        G::sgUvFramePixel(s.frame, s.uv[kk].st, s.uv[kk].dSTdx, s.uv[kk].dSTdy);
            }
            s.surfGrad = glm::vec3(0.0f);
        }
        // groupOrder() without allocating per pixel.
        const std::vector<PlanLayer>& layers = plan.groups[g];
        for (const PlanLayer& pl : layers)
            if (!pl.layer->kind->batch) layer(pl, s);
        for (const LayerKind* k : plan.kinds) {
            if (!k->batch) continue;
            for (const PlanLayer& pl : layers)
                if (pl.layer->kind == k) layer(pl, s);
        }
        if (lateBaseColor) *lateBaseColor = baseColor(s);
        return G::sgResolve(s.frame, s.surfGrad);
    }
};

} // namespace

glm::vec4 shadePixelCpu(const MaterialPlan& plan, const DrawUniforms& u,
                        const std::vector<G::sampler2D>& smp, const std::vector<std::any>& kindData,
                        const PixelInputs& in) {
    const CpuShader sh{plan, u, smp, kindData, in};
    CpuShadeState s = sh.prologue();
    const glm::vec3 baseNormal = s.frame.resolveSign * s.frame.nrmBase;
    const bool lateBaseColor = movesSurface(plan);
    glm::vec3 baseColor = lateBaseColor ? glm::vec3(0.0f) : sh.baseColor(s);
    glm::vec3 nrm = sh.group(0, s, glm::vec3(0.0f), lateBaseColor ? &baseColor : nullptr);
    const glm::vec3 surfGradOut = s.surfGrad;
    glm::vec3 tangentOut = s.uv[0].vT, bitangentOut = s.uv[0].vB;
    for (size_t g = 1; g < plan.groups.size(); ++g) {
        if (plan.uber && !(u.uberFlags[size_t(plan.groupUberIndex[g])] > 0.5f)) continue;
        nrm = sh.group(g, s, nrm);
    }
    const float roughness =
        plan.antialias ? G::sgAaRoughness(u.roughness, s.slopeCov) : u.roughness;
    glm::vec3 color = G::sgShadeAmbient(nrm, u.ambient, baseColor);
    // emitShading()'s lit position (s.surfOffset is zero unless a layer moved the surface).
    const glm::vec3 lit = (plan.displacementUvSet >= 0 ? in.relPosLit : in.relPos) + s.surfOffset;
    for (int i = 0; i < plan.lightCount; ++i) {
        color += G::sgShadeLight(nrm, lit, u.lights[size_t(2 * i)], u.lights[size_t(2 * i + 1)],
                                 baseColor, roughness);
    }
    const bool hasUv0 = plan.uvCount > 0;
    if (!hasUv0) tangentOut = bitangentOut = glm::vec3(0.0f);
    if (plan.adaptive && u.aov == int(Aov::Patch)) return in.patchAov;
    return G::sgAovValue(u.aov, color, nrm, surfGradOut, tangentOut, bitangentOut, baseNormal,
                         hasUv0 ? in.uv[0] : glm::vec2(0.0f), in.primId + 1.0f + u.primBase);
}

} // namespace detail

} // namespace sg::render
