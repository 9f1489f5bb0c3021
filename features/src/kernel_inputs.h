// Parity-record generators of the feature-curve evaluation kernels (named by
// the kernel list in shaders/sg/features/kernels.glsl), and a writer of
// records by field name (slots from the table, so packers never hard-code
// them).
#pragma once

#include <cstdint>
#include <vector>

#include "surfgrad/base/contract.h"
#include "surfgrad/features/feature_maps.h"

namespace sg::features::detail {

// Writes fields of one record (kEvalInStride floats, zeroed first) by name.
class RecordWriter {
public:
    RecordWriter(const std::vector<record::Field>& layout, float* rec)
        : layout_(layout), rec_(rec) {
        for (int k = 0; k < kEvalInStride; ++k) rec_[k] = 0.0f;
    }
    void set(const char* name, float v) { at(name, 1)[0] = v; }
    void set(const char* name, glm::vec2 v) {
        float* p = at(name, 2);
        p[0] = v.x;
        p[1] = v.y;
    }
    void set(const char* name, glm::vec3 v) {
        float* p = at(name, 3);
        for (int k = 0; k < 3; ++k) p[k] = v[k];
    }
    void set(const char* name, glm::vec4 v) {
        float* p = at(name, 4);
        for (int k = 0; k < 4; ++k) p[k] = v[k];
    }
    // A uint field: two exact 16-bit halves.
    void setWord(const char* name, uint32_t w) {
        float* p = at(name, 2);
        p[0] = float(w & 0xFFFFu);
        p[1] = float(w >> 16);
    }

private:
    float* at(const char* name, int floats) {
        const record::Field* f = record::findField(layout_, name);
        SG_EXPECTS(f && f->floats == floats, "a field of the kernel's record, of that width");
        (void)floats;
        return rec_ + f->slot;
    }
    const std::vector<record::Field>& layout_;
    float* rec_;
};

std::vector<float> kernelInputsEval(uint32_t seed);
std::vector<float> kernelInputsProfile(uint32_t seed);
std::vector<float> kernelInputsNearPiece(uint32_t seed);

} // namespace sg::features::detail
