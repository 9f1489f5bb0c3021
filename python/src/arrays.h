// numpy <-> C++ for the Python module: the one place that checks array
// arguments and turns C++ results into numpy arrays (docs/python.md,
// "Arrays").
//
// In: an argument is read in place (no copy) when it is a numpy array of the
// expected dtype (float32 or uint32; no conversion), C-contiguous, aligned,
// of the expected shape. Anything else raises TypeError (not an array, wrong
// dtype) or ValueError (shape, contiguity, alignment) with a message naming
// the argument, what was expected and what was given, e.g.
//   "positions: expected a float32 array of shape (N, 3), got float64 (4, 3);
//    convert with np.ascontiguousarray(x, dtype=np.float32)".
// Values are checked by the callers (finite, index ranges) before anything
// reaches a C++ precondition: a contract violation would abort the
// interpreter.
//
// Out: results move their std::vector into a capsule that owns it, so the
// numpy array is the C++ buffer (no copy). Views of a mesh's arrays keep
// the mesh alive through their base object.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

// A dimension of an expected shape: a fixed size, or kAny (then `name`
// says what it counts, e.g. "N").
inline constexpr py::ssize_t kAny = -1;
struct Dim {
    py::ssize_t size = kAny;
    const char* name = "N";
};

// The array `obj` as a C-contiguous array of T (float or uint32_t) of the
// given shape, without copying; throws TypeError/ValueError as above.
// `arg` names the argument in messages.
template <class T>
py::array_t<T> requireArray(py::handle obj, const char* arg, std::initializer_list<Dim> shape);

// The same for arrays of rank 1 or 2 whose last dimension is `width`
// (width 1: rank 1), e.g. indices given as (T, 3) or flat (3T,).
template <class T>
py::array_t<T> requireRows(py::handle obj, const char* arg, py::ssize_t width);

// Spans over a checked array (the rows as glm vectors; glm's vecN of float
// has the layout of N floats).
template <class V>
std::span<const V> rowsOf(const py::array_t<float>& a) {
    static_assert(sizeof(V) % sizeof(float) == 0);
    const size_t rows = size_t(a.size()) / (sizeof(V) / sizeof(float));
    return {reinterpret_cast<const V*>(a.data()), rows};
}
inline std::span<const uint32_t> valuesOf(const py::array_t<uint32_t>& a) {
    return {a.data(), size_t(a.size())};
}

// Throws ValueError naming `arg` and the first non-finite value (its row
// and column) when a float array holds NaN or Inf.
void requireFinite(const py::array_t<float>& a, const char* arg);
// The same, and every |value| <= bound (ValueError naming the value).
void requireBounded(const py::array_t<float>& a, const char* arg, float bound);
// Throws ValueError naming `arg` and the first index >= limit.
void requireIndicesBelow(std::span<const uint32_t> indices, size_t limit, const char* arg,
                         const char* what);

// A new array that owns `values` (moved into a capsule; no copy). Rows of
// glm vectors become a last dimension of their width.
template <class T>
py::array moveToArray(std::vector<T>&& values, std::vector<py::ssize_t> shape);
py::array moveToArray(std::vector<glm::vec2>&& values);
py::array moveToArray(std::vector<glm::vec3>&& values);
py::array moveToArray(std::vector<glm::vec4>&& values);

// A writable view of `data` (rows x width floats or uint32s) whose base is
// `owner` (the Python object that owns the buffer; it stays alive while the
// view does). rows == 0 gives an empty array of shape (0, width).
py::array viewOf(float* data, size_t rows, size_t width, py::handle owner);
py::array viewOf(uint32_t* data, size_t rows, size_t width, py::handle owner);

// Copies a checked array into a vector of glm rows (assignment to a mesh
// attribute).
template <class V>
std::vector<V> copyRows(const py::array_t<float>& a) {
    auto rows = rowsOf<V>(a);
    return {rows.begin(), rows.end()};
}

// A copy of a C++ array as a new numpy array: glm rows as (N, width),
// scalars as (N,). For attributes read as copies (tags, frames, weights).
template <class T>
py::array copyToArray(const std::vector<T>& values) {
    auto copy = values;
    if constexpr (std::is_arithmetic_v<T>) {
        const auto n = py::ssize_t(copy.size());
        return moveToArray(std::move(copy), {n});
    } else {
        return moveToArray(std::move(copy));
    }
}

// An optional Python callable handed to C++ as a progress callback that
// the C++ side calls with the GIL released (from the calling thread or a
// worker thread, one call at a time). The call takes the GIL; the first
// Python exception it raises stops further calls and is raised again by
// rethrow() once the C++ work is back. Keep the object alive while the
// callback may be called.
class PyCallback {
public:
    explicit PyCallback(py::object callable) : callable_(std::move(callable)) {}
    // A std::function calling the callable with `convert(args...)`'s
    // arguments (a tuple), or an empty function when the callable is None.
    template <class... Args, class Convert>
    std::function<void(Args...)> bind(Convert convert) {
        if (callable_.is_none()) return {};
        return [this, convert](Args... args) {
            py::gil_scoped_acquire acquire;
            if (error_) return;
            try {
                callable_(*convert(args...));
            } catch (py::error_already_set& e) {
                error_ = std::move(e);
            }
        };
    }
    void rethrow() {
        if (error_) throw std::move(*error_);
    }

private:
    py::object callable_;
    std::optional<py::error_already_set> error_;
};

// Checks a thread count (0..kMaxThreads) and throws ValueError naming
// `arg` otherwise.
int requireThreads(int threads, const char* arg = "threads");

// Raises ValueError("<arg>: unknown value 'x'; expected one of a, b, c").
[[noreturn]] void throwUnknownName(const char* arg, const std::string& given,
                                   std::initializer_list<const char*> names);

} // namespace sg::python
