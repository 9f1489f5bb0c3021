// The layer-kind registry as a whole: every kind is complete (a GLSL file
// that is embedded, a GLSL statement and its CPU call, a unique name and
// signature code, a parameter table the parser, viewer and docs can use),
// and docs/scene.md documents every kind, every field of every kind's table
// and every modifier with its fields.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "layer_kind.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::render::test {
namespace {

std::string readDoc(const char* name) {
    std::ifstream f(std::string(SURFGRAD_SOURCE_DIR) + "/docs/" + name);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

TEST(LayerRegistry, EveryKindIsComplete) {
    std::set<std::string> names, codes;
    for (const LayerKind* k : layerKinds()) {
        SCOPED_TRACE(k->name);
        EXPECT_TRUE(names.insert(k->name).second) << "duplicate name";
        EXPECT_TRUE(codes.insert(k->sigCode).second) << "duplicate signature code";
        EXPECT_EQ(findLayerKind(k->name), k);
        std::set<std::string> fields;
        for (const ParamSpec& p : k->params) {
            EXPECT_TRUE(fields.insert(p.json).second) << "duplicate field " << p.json;
            EXPECT_NE(std::string(p.doc), "") << p.json << " has no doc line";
            if (p.slider) {
                EXPECT_EQ(p.type, ParamType::Number) << p.json;
                EXPECT_TRUE(p.floatRef) << p.json;
            }
        }
        if (k->group) continue;
        ASSERT_NE(k->glslFile, nullptr);
        EXPECT_NE(sg::shaders::find(k->glslFile), nullptr) << k->glslFile << " is not embedded";
        if (k->modifiers) {
            EXPECT_NE(sg::shaders::find(k->modifiers->glslFile), nullptr) << "modifier file";
        }
        EXPECT_TRUE(k->emit.glsl || k->batch) << "no GLSL statement";
        EXPECT_NE(k->emit.cpu, nullptr) << "no CPU call";
        EXPECT_NE(k->makeParams, nullptr);
        EXPECT_GT(k->recordCount(), 0);
        // A layer made from the registry has the kind's parameter type.
        Layer L = makeLayer(k->name);
        EXPECT_EQ(L.kind, k);
        EXPECT_TRUE(L.kindParams.has_value());
    }
    std::set<std::string> mods;
    for (const ModifierKind* m : modifierKinds()) {
        EXPECT_TRUE(mods.insert(m->name).second) << m->name;
        EXPECT_EQ(findModifierKind(m->name), m);
        EXPECT_TRUE(m->parse && m->pack && m->emit.glsl && m->emit.cpu) << m->name;
        if (m->warpsLookup) {
            EXPECT_TRUE(m->warp.glsl && m->warp.cpu) << m->name;
        }
    }
}

// The row of docs/scene.md's layer table for `kind` ("| `kind` | ...").
std::string docRow(const std::string& doc, const std::string& kind) {
    size_t p = doc.find("\n| `" + kind + "` |");
    if (p == std::string::npos) return "";
    return doc.substr(p + 1, doc.find('\n', p + 1) - p - 1);
}

TEST(LayerRegistry, SceneDocsListEveryKindAndField) {
    const std::string doc = readDoc("scene.md");
    ASSERT_FALSE(doc.empty());
    const size_t table = doc.find("| `type` | fields | math |");
    ASSERT_NE(table, std::string::npos) << "the layer table of docs/scene.md";
    std::set<std::string> documented;
    for (size_t p = doc.find("\n| `", table); p != std::string::npos && p < doc.find("\n\n", table);
         p = doc.find("\n| `", p + 1)) {
        documented.insert(doc.substr(p + 4, doc.find('`', p + 4) - p - 4));
    }
    std::set<std::string> registered;
    for (const LayerKind* k : layerKinds()) {
        registered.insert(k->name);
        std::string row = docRow(doc, k->name);
        ASSERT_FALSE(row.empty()) << "docs/scene.md has no row for " << k->name;
        for (const ParamSpec& p : k->params) {
            EXPECT_NE(row.find(std::string("`") + p.json + "`"), std::string::npos)
                << "docs/scene.md's row of " << k->name << " does not name `" << p.json << "`";
        }
    }
    EXPECT_EQ(documented, registered) << "the layer table lists exactly the registered kinds";
    const size_t mods = doc.find("Modifiers (`modifiers`");
    ASSERT_NE(mods, std::string::npos);
    const std::string para = doc.substr(mods, doc.find("\n\n", mods) - mods);
    for (const ModifierKind* m : modifierKinds()) {
        EXPECT_NE(para.find(std::string("{\"type\": \"") + m->name + "\""), std::string::npos)
            << m->name;
        for (const char* f : m->fields)
            EXPECT_NE(para.find(std::string("\"") + f + "\""), std::string::npos)
                << m->name << "." << f;
    }
}

} // namespace
} // namespace sg::render::test
