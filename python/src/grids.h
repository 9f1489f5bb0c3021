// Normal-map grids (surfgrad/normalmap/operations.h) out to numpy: the one place a
// Grid becomes an (H, W[, C]) array, row 0 the bottom row as in C++. The
// grid's storage moves into a capsule the array owns (no copy). Float
// grids (float, vec2, vec3, vec4) give float32 arrays, uint8 grids uint8.
#pragma once

#include <type_traits>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>

#include "surfgrad/normalmap/operations.h"

namespace sg::python {

namespace py = pybind11;

template <class T>
py::array gridToArray(sg::normalmap::Grid<T>&& g) {
    using Scalar = std::conditional_t<std::is_same_v<T, uint8_t>, uint8_t, float>;
    constexpr py::ssize_t c = sizeof(T) / sizeof(Scalar);
    std::vector<py::ssize_t> shape{g.height, g.width};
    if (c > 1) shape.push_back(c);
    auto* heap = new std::vector<T>(std::move(g.v));
    py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<Scalar>(shape, reinterpret_cast<const Scalar*>(heap->data()), owner);
}

} // namespace sg::python
