// The C++ table side of the kernel-record convention of
// shaders/sg/record.glsl: from a field list (a macro expanding to
// F(type, name, doc) per field, in record order), SG_REC_FIELDS(LIST)
// builds the fields with their widths in floats and their first slots, so
// the C++ table, the packers of test records and the GLSL readers all come
// from the one declaration. Expand it where the GLSL types (vec2, ..., uint)
// name sg::glsl's (e.g. inside `using namespace sg::glsl;`).
#pragma once

#include <string>
#include <vector>

#include "surfgrad/shaders/glsl_cpp.h"

namespace sg::record {

struct Field {
    std::string name; // as declared
    int floats = 0;   // width in the record
    int slot = 0;     // first float
    std::string doc;  // one line: meaning, units, space
};

// Floats per field type (record.glsl): uint takes two 16-bit halves.
template <class T>
constexpr int floatsOf();
template <>
constexpr int floatsOf<float>() {
    return 1;
}
template <>
constexpr int floatsOf<int>() {
    return 1;
}
template <>
constexpr int floatsOf<bool>() {
    return 1;
}
template <>
constexpr int floatsOf<unsigned int>() {
    return 2;
}
template <>
constexpr int floatsOf<glm::vec2>() {
    return 2;
}
template <>
constexpr int floatsOf<glm::vec3>() {
    return 3;
}
template <>
constexpr int floatsOf<glm::vec4>() {
    return 4;
}
template <>
constexpr int floatsOf<glm::mat4>() {
    return 16;
}

inline std::vector<Field> withSlots(std::vector<Field> fields) {
    int at = 0;
    for (Field& f : fields) {
        f.slot = at;
        at += f.floats;
    }
    return fields;
}

// Total floats of a field list.
inline int recordFloats(const std::vector<Field>& fields) {
    return fields.empty() ? 0 : fields.back().slot + fields.back().floats;
}

// The field called `name`, or nullptr.
inline const Field* findField(const std::vector<Field>& fields, const std::string& name) {
    for (const Field& f : fields)
        if (f.name == name) return &f;
    return nullptr;
}

} // namespace sg::record

#define SG_REC_CPP_FIELD(T, name, doc)                                                             \
    ::sg::record::Field{#name, ::sg::record::floatsOf<T>(), 0, doc},
#define SG_REC_FIELDS(LIST) ::sg::record::withSlots({LIST(SG_REC_CPP_FIELD)})
