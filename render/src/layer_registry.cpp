// The layer-kind registry: every kind of bump layer the renderer knows, in
// schema order (the order of the scene's "type" list and of the uber-shader
// stand-ins). Each kind is a unit in shaders/sg/render/: layer_<kind>.glsl
// and layer_<kind>.cpp, which defines `const LayerKind& <kind>LayerKind()`.
// Adding a kind is one line here (docs/architecture.md, "Adding a layer kind").
#include "layer_kind.h"

#define SG_RENDER_LAYER_KINDS(X)                                                                   \
    X(uvNormal)                                                                                    \
    X(objectNormal)                                                                                \
    X(height)                                                                                      \
    X(parallax)                                                                                    \
    X(pom)                                                                                         \
    X(derivMap)                                                                                    \
    X(triplanar)                                                                                   \
    X(decal)                                                                                       \
    X(noise)                                                                                       \
    X(feature)                                                                                     \
    X(postResolve)

namespace sg::render {

#define SG_DECLARE_KIND(k) const LayerKind& k##LayerKind();
SG_RENDER_LAYER_KINDS(SG_DECLARE_KIND)
#undef SG_DECLARE_KIND

const std::vector<const LayerKind*>& layerKinds() {
#define SG_LIST_KIND(k) &k##LayerKind(),
    static const std::vector<const LayerKind*> kinds = {SG_RENDER_LAYER_KINDS(SG_LIST_KIND)};
#undef SG_LIST_KIND
    return kinds;
}

} // namespace sg::render
