// The C++ packer and the GLSL unpackers of every layer kind agree, slot by
// slot. Generated from the registry (render/src/layer_kind.h): for
// every kind and every record layout (one sgUnpack* function each) the
// records are unpacked through the GLSL function twice, on the GPU (a
// compute shader built from the layout's field list) and through its C++
// build, and every field is compared with the value packed for it: bitwise
// for ints and bools (as 32-bit words), exactly for floats (the unpackers
// copy them). A layout that puts a field in a slot its unpacker does not
// read it from fails, whichever two slots are swapped.
//   1. Random field values (distinct per field and trial) packed by the
//      layouts' slots: catches any disagreement between layout and unpacker.
//   2. Scenes with a layer of every kind (and a post-resolve group of them)
//      with random parameters from each kind's table, through parseScene,
//      planMaterial and packLayerRecords (the path both renderers use):
//      each layer's records unpack to the values its layout computes from
//      the layer's parameters.
// Derivative-space modifiers pass their records to their GLSL functions
// unchanged (deriv_mods.glsl reads op.y, op.z), so they have no unpacker.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <random>

#include "layer_kind.h"
#include "render_test_util.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::render::test {
namespace {

int wordCount(const RecordLayout& l) {
    int n = 0;
    for (const auto& f : l.fields) n += componentCount(f.type);
    return n;
}

// The GLSL expression giving a field's component c as a uint.
std::string wordExpr(const RecordField& f, int c) {
    static const char* comp[] = {".x", ".y", ".z"};
    std::string v = "p." + f.glsl;
    switch (f.type) {
    case FieldType::Int:
        return "uint(" + v + ")";
    case FieldType::Bool:
        return "(" + v + " ? 1u : 0u)";
    case FieldType::Float:
        return "floatBitsToUint(" + v + ")";
    default:
        return "floatBitsToUint(" + v + comp[c] + ")";
    }
}

// A compute program that unpacks one record set per invocation and writes
// the fields as 32-bit words in the layout's order.
sg::gl::Program unpackProgram(const LayerKind& kind, const RecordLayout& l) {
    std::string body =
        "#include \"" + (l.glslFile.empty() ? std::string(kind.glslFile) : l.glslFile) + "\"\n";
    body += "layout(local_size_x = " + std::to_string(sg::gl::kComputeGroupSize) +
            ") in;\n"
            "layout(std430, binding = 0) readonly buffer InRecords { vec4 inRec[]; };\n"
            "layout(std430, binding = 1) writeonly buffer OutWords { uint outWords[]; };\n"
            "uniform uint uCount;\n"
            "void main() {\n"
            "    uint i = gl_GlobalInvocationID.x;\n"
            "    if (i >= uCount) return;\n"
            "    uint r = i * " +
            std::to_string(l.count) +
            "u;\n"
            "    " +
            l.structType + " p = " + l.unpack + "(";
    for (int i = 0; i < l.count; ++i)
        body += (i ? ", " : "") + std::string("inRec[r + ") + std::to_string(i) + "u]";
    body += ");\n    uint o = i * " + std::to_string(wordCount(l)) + "u;\n";
    int w = 0;
    for (const auto& f : l.fields)
        for (int c = 0; c < componentCount(f.type); ++c)
            body += "    outWords[o + " + std::to_string(w++) + "u] = " + wordExpr(f, c) + ";\n";
    body += "}\n";
    auto src = sg::shaders::assemble(body, "(records test: " + l.unpack + ")");
    return sg::gl::Program({{sg::gl::Stage::Compute, src}});
}

// Expected words of a field from the value packed for it.
void expectedWords(const RecordField& f, glm::vec3 v, uint32_t* w) {
    switch (f.type) {
    case FieldType::Int:
        w[0] = uint32_t(int(v.x));
        return;
    case FieldType::Bool:
        w[0] = v.x > 0.5f ? 1u : 0u;
        return;
    default:
        for (int c = 0; c < componentCount(f.type); ++c) std::memcpy(&w[c], &v[c], 4);
    }
}

// Record sets (count vec4 each, as floats) and the words every field must
// unpack to; compared on the GPU and through the C++ build.
struct Batch {
    std::vector<float> records;
    std::vector<uint32_t> expected;
    size_t n = 0;
};

void checkBatch(const LayerKind& kind, const RecordLayout& l, const Batch& b) {
    const int words = wordCount(l), stride = 4 * l.count;
    sg::gl::Program prog = unpackProgram(kind, l);
    std::vector<float> gpuOut = sg::gl::runCompute(prog, b.records, stride, words, b.n);
    size_t gpuBad = 0, cpuBad = 0;
    for (size_t i = 0; i < b.n; ++i) {
        std::vector<glm::vec4> rec(size_t(l.count));
        std::memcpy(rec.data(), &b.records[i * size_t(stride)], sizeof(float) * size_t(stride));
        std::any unpacked = l.unpackCpu(rec.data());
        std::vector<uint32_t> cpu(static_cast<size_t>(words), 0u);
        int w = 0;
        for (const auto& f : l.fields) {
            f.read(unpacked, &cpu[size_t(w)]);
            for (int c = 0; c < componentCount(f.type); ++c, ++w) {
                const uint32_t want = b.expected[i * size_t(words) + size_t(w)];
                uint32_t gpu;
                std::memcpy(&gpu, &gpuOut[i * size_t(words) + size_t(w)], 4);
                if (gpu != want && gpuBad++ < 5)
                    ADD_FAILURE() << l.unpack << " on the GPU: field " << f.glsl << " component "
                                  << c << " is " << gpu << ", packed " << want;
                if (cpu[size_t(w)] != want && cpuBad++ < 5)
                    ADD_FAILURE() << l.unpack << " in C++: field " << f.glsl << " component " << c
                                  << " is " << cpu[size_t(w)] << ", packed " << want;
            }
        }
    }
    EXPECT_EQ(gpuBad, 0u) << kind.name << ": " << l.unpack;
    EXPECT_EQ(cpuBad, 0u) << kind.name << ": " << l.unpack;
}

TEST(LayerRecords, LayoutsAndUnpackersAgreeOnEverySlot) {
    gpu(); // the GL context
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> real(-1000.0f, 1000.0f);
    std::uniform_int_distribution<int> integer(-1, 1000), coin(0, 1);
    int layouts = 0;
    for (const LayerKind* kind : layerKinds()) {
        for (const RecordLayout& l : kind->records) {
            SCOPED_TRACE(std::string(kind->name) + ": " + l.unpack);
            ++layouts;
            // Every slot read once, inside the unpacker's records.
            std::set<std::pair<int, int>> used;
            for (const auto& f : l.fields)
                for (const Slot& s : f.slots) {
                    EXPECT_TRUE(s.record >= 0 && s.record < l.count && s.component >= 0 &&
                                s.component < 4)
                        << f.glsl;
                    EXPECT_TRUE(used.insert({s.record, s.component}).second)
                        << f.glsl << " shares a slot";
                }
            Batch b;
            b.n = 256;
            const int words = wordCount(l);
            b.expected.resize(b.n * size_t(words));
            for (size_t i = 0; i < b.n; ++i) {
                std::vector<glm::vec4> rec(size_t(l.count), glm::vec4(0.0f));
                int w = 0;
                for (const auto& f : l.fields) {
                    glm::vec3 v(real(rng), real(rng), real(rng));
                    if (f.type == FieldType::Int) v.x = float(integer(rng));
                    if (f.type == FieldType::Bool) v.x = float(coin(rng));
                    packField(f, v, rec.data());
                    expectedWords(f, v, &b.expected[i * size_t(words) + size_t(w)]);
                    w += componentCount(f.type);
                }
                for (const auto& r : rec) b.records.insert(b.records.end(), {r.x, r.y, r.z, r.w});
            }
            checkBatch(*kind, l, b);
        }
    }
    EXPECT_GE(layouts, 9) << "every kind with records has its layouts";
}

// A JSON value for a table entry, random within its validation range.
std::string randomValue(const ParamSpec& p, std::mt19937& rng) {
    auto uni = [&](double lo, double hi) {
        return std::uniform_real_distribution<double>(std::max(lo, -8.0), std::min(hi, 8.0))(rng);
    };
    switch (p.type) {
    case ParamType::Number: {
        double x = uni(p.lo, p.hi);
        if (p.loOpen && x <= p.lo) x = p.lo + 0.5;
        return std::to_string(x);
    }
    case ParamType::Integer:
        return std::to_string(std::uniform_int_distribution<int>(
            int(p.lo), std::min(int(p.hi), int(p.lo) + 16))(rng));
    case ParamType::Boolean:
        return rng() % 2 ? "true" : "false";
    case ParamType::Choice:
        return std::string("\"") + p.choices[rng() % p.choices.size()].first + "\"";
    case ParamType::Vec3:
        return "[" + std::to_string(uni(p.lo, p.hi)) + ", " + std::to_string(uni(p.lo, p.hi)) +
               ", " + std::to_string(uni(p.lo, p.hi)) + "]";
    default:
        return "";
    }
}

constexpr const char* kRecordsMesh =
    R"({"procedural": {"type": "sphere", "segments": 8, "uv_sets": 4}})";

// A layer of the kind: its example plus random values for its table
// entries, drawn again until the layer is valid on its own (random values
// may break a cross-field rule, e.g. w0 < width).
std::string randomLayer(const LayerKind& k, std::mt19937& rng) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
        std::string j = std::string("{\"type\": \"") + k.name + "\"";
        if (*k.example) j += std::string(", ") + k.example;
        for (const ParamSpec& p : k.params) {
            std::string v = randomValue(p, rng);
            if (!v.empty()) j += std::string(", \"") + p.json + "\": " + v;
        }
        j += "}";
        try {
            (void)sceneFromJson(oneMaterialScene(j, kRecordsMesh));
            return j;
        } catch (const io::InputError&) {
        }
    }
    ADD_FAILURE() << "no valid random layer of " << k.name;
    return "";
}

TEST(LayerRecords, PackedScenesUnpackToTheLayersParameters) {
    gpu();
    std::mt19937 rng(7);
    std::map<std::pair<const LayerKind*, size_t>, Batch> batches;
    for (int trial = 0; trial < 8; ++trial) {
        // A layer of every kind, and a post-resolve group of them.
        std::string layers, grouped;
        for (const LayerKind* k : layerKinds()) {
            if (k->group) continue;
            layers += (layers.empty() ? "" : ", ") + randomLayer(*k, rng);
            grouped += (grouped.empty() ? "" : ", ") + randomLayer(*k, rng);
        }
        layers += R"(, {"type": "post_resolve", "layers": [)" + grouped + "]}";
        Scene s = sceneFromJson(oneMaterialScene(layers, kRecordsMesh));
        SceneAssets a = loadAssets(s);
        MaterialPlan plan = planMaterial(s, a, 0, 0);
        View view = makeView(s, a);
        view.cameraPos += glm::dvec3(std::uniform_real_distribution<float>(-5.0f, 5.0f)(rng));
        std::vector<glm::vec4> records = packLayerRecords(plan, view);
        for (const auto& group : plan.groups)
            for (const PlanLayer& pl : group) {
                const Layer& L = *pl.layer;
                for (size_t li = 0; li < L.kind->records.size(); ++li) {
                    const RecordLayout& l = L.kind->records[li];
                    Batch& b = batches[{L.kind, li}];
                    const glm::vec4* r = &records[size_t(pl.record + l.first)];
                    for (int i = 0; i < l.count; ++i)
                        b.records.insert(b.records.end(), {r[i].x, r[i].y, r[i].z, r[i].w});
                    std::any prepared = l.prepare ? l.prepare(L) : std::any();
                    PackInput in{L, view, nullptr, prepared};
                    for (const auto& f : l.fields) {
                        uint32_t w[3];
                        expectedWords(f, f.value(in), w);
                        b.expected.insert(b.expected.end(), w, w + componentCount(f.type));
                    }
                    ++b.n;
                }
            }
    }
    size_t kindsWithRecords = 0;
    for (const LayerKind* k : layerKinds()) kindsWithRecords += !k->records.empty();
    std::set<const LayerKind*> seen;
    for (const auto& [key, b] : batches) {
        seen.insert(key.first);
        SCOPED_TRACE(key.first->name);
        std::printf("%s %s: %zu layers\n", key.first->name,
                    key.first->records[key.second].unpack.c_str(), b.n);
        checkBatch(*key.first, key.first->records[key.second], b);
    }
    EXPECT_EQ(seen.size(), kindsWithRecords) << "a layer of every kind was packed";
}

} // namespace
} // namespace sg::render::test
