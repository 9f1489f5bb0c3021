// numpy <-> C++ checks and conversions of the Python module (arrays.h).
#include "arrays.h"

#include <cmath>
#include <functional>
#include <sstream>

#include "surfgrad/base/threads.h"

namespace sg::python {

namespace {

template <class T>
constexpr const char* dtypeName() {
    if constexpr (std::is_same_v<T, float>) {
        return "float32";
    } else {
        return "uint32";
    }
}

template <class T>
bool hasDtype(const py::array& a) {
    const py::dtype dt = a.dtype();
    const char kind = std::is_same_v<T, float> ? 'f' : 'u';
    return dt.kind() == kind && dt.itemsize() == py::ssize_t(sizeof(T)) &&
           dt.attr("isnative").template cast<bool>();
}

std::string shapeText(std::initializer_list<Dim> shape) {
    std::string s = "(";
    bool first = true;
    for (const Dim& d : shape) {
        if (!first) s += ", ";
        first = false;
        s += d.size == kAny ? std::string(d.name) : std::to_string(d.size);
    }
    return s + (shape.size() == 1 ? ",)" : ")");
}

std::string shapeText(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) {
        if (k) s += ", ";
        s += std::to_string(a.shape(k));
    }
    return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string given(py::handle obj) {
    if (!py::isinstance<py::array>(obj)) {
        return std::string(py::str(py::type::of(obj).attr("__name__")));
    }
    auto a = py::reinterpret_borrow<py::array>(obj);
    return std::string(py::str(a.dtype())) + " array of shape " + shapeText(a);
}

template <class T>
[[noreturn]] void fail(py::handle obj, const char* arg, const std::string& expected, bool typeError,
                       const char* why = nullptr) {
    std::string msg = std::string(arg) + ": expected a " + dtypeName<T>() + " array of shape " +
                      expected + ", got " + given(obj);
    if (why) msg += std::string(" (") + why + ")";
    msg += std::string("; convert with np.ascontiguousarray(x, dtype=np.") + dtypeName<T>() + ")";
    if (typeError) throw py::type_error(msg);
    throw py::value_error(msg);
}

template <class T>
py::array_t<T> checked(py::handle obj, const char* arg, const std::string& expected,
                       const std::function<bool(const py::array&)>& shapeOk) {
    if (!py::isinstance<py::array>(obj)) fail<T>(obj, arg, expected, true);
    auto a = py::reinterpret_borrow<py::array>(obj);
    if (!hasDtype<T>(a)) fail<T>(obj, arg, expected, true);
    if (!shapeOk(a)) fail<T>(obj, arg, expected, false);
    if (!(a.flags() & py::array::c_style)) fail<T>(obj, arg, expected, false, "not C-contiguous");
    if (reinterpret_cast<uintptr_t>(a.data()) % alignof(T) != 0) {
        fail<T>(obj, arg, expected, false, "not aligned");
    }
    return py::reinterpret_borrow<py::array_t<T>>(a);
}

template <class T>
void releaseVector(void* p) {
    delete static_cast<std::vector<T>*>(p);
}

template <class T>
py::array ownedArray(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* heap = new std::vector<T>(std::move(values));
    py::capsule owner(heap, &releaseVector<T>);
    using Scalar = std::conditional_t<std::is_integral_v<T>, T, float>;
    return py::array_t<Scalar>(std::move(shape), reinterpret_cast<const Scalar*>(heap->data()),
                               owner);
}

} // namespace

template <class T>
py::array_t<T> requireArray(py::handle obj, const char* arg, std::initializer_list<Dim> shape) {
    const std::string expected = shapeText(shape);
    return checked<T>(obj, arg, expected, [&](const py::array& a) {
        if (a.ndim() != py::ssize_t(shape.size())) return false;
        py::ssize_t k = 0;
        for (const Dim& d : shape) {
            if (d.size != kAny && a.shape(k) != d.size) return false;
            ++k;
        }
        return true;
    });
}

template <class T>
py::array_t<T> requireRows(py::handle obj, const char* arg, py::ssize_t width) {
    const std::string expected =
        width == 1 ? std::string("(N,)")
                   : "(N, " + std::to_string(width) + ") or (" + std::to_string(width) + "N,)";
    return checked<T>(obj, arg, expected, [&](const py::array& a) {
        if (a.ndim() == 1) return a.shape(0) % width == 0;
        return width > 1 && a.ndim() == 2 && a.shape(1) == width;
    });
}

template py::array_t<float> requireArray<float>(py::handle, const char*,
                                                std::initializer_list<Dim>);
template py::array_t<uint32_t> requireArray<uint32_t>(py::handle, const char*,
                                                      std::initializer_list<Dim>);
template py::array_t<float> requireRows<float>(py::handle, const char*, py::ssize_t);
template py::array_t<uint32_t> requireRows<uint32_t>(py::handle, const char*, py::ssize_t);

void requireFinite(const py::array_t<float>& a, const char* arg) {
    const float* v = a.data();
    const size_t n = size_t(a.size());
    for (size_t k = 0; k < n; ++k) {
        if (!std::isfinite(v[k])) {
            const size_t width = a.ndim() >= 2 ? size_t(a.size() / a.shape(0)) : 1;
            std::ostringstream msg;
            msg << arg << ": value " << v[k] << " at row " << k / width;
            if (width > 1) msg << ", column " << k % width;
            msg << " is not finite";
            throw py::value_error(msg.str());
        }
    }
}

void requireBounded(const py::array_t<float>& a, const char* arg, float bound) {
    requireFinite(a, arg);
    const float* v = a.data();
    const size_t n = size_t(a.size());
    for (size_t k = 0; k < n; ++k) {
        if (std::fabs(v[k]) > bound) {
            const size_t width = a.ndim() >= 2 ? size_t(a.size() / a.shape(0)) : 1;
            std::ostringstream msg;
            msg << arg << ": value " << v[k] << " at row " << k / width;
            if (width > 1) msg << ", column " << k % width;
            msg << " is beyond +-" << bound;
            throw py::value_error(msg.str());
        }
    }
}

void requireIndicesBelow(std::span<const uint32_t> indices, size_t limit, const char* arg,
                         const char* what) {
    for (size_t k = 0; k < indices.size(); ++k) {
        if (indices[k] >= limit) {
            throw py::value_error(std::string(arg) + ": entry " + std::to_string(k) + " is " +
                                  std::to_string(indices[k]) + ", but there are only " +
                                  std::to_string(limit) + " " + what);
        }
    }
}

template <class T>
py::array moveToArray(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    return ownedArray(std::move(values), std::move(shape));
}
template py::array moveToArray<float>(std::vector<float>&&, std::vector<py::ssize_t>);
template py::array moveToArray<uint32_t>(std::vector<uint32_t>&&, std::vector<py::ssize_t>);
template py::array moveToArray<uint8_t>(std::vector<uint8_t>&&, std::vector<py::ssize_t>);
template py::array moveToArray<int32_t>(std::vector<int32_t>&&, std::vector<py::ssize_t>);
template py::array moveToArray<glm::vec2>(std::vector<glm::vec2>&&, std::vector<py::ssize_t>);
template py::array moveToArray<glm::vec3>(std::vector<glm::vec3>&&, std::vector<py::ssize_t>);
template py::array moveToArray<glm::vec4>(std::vector<glm::vec4>&&, std::vector<py::ssize_t>);

py::array moveToArray(std::vector<glm::vec2>&& values) {
    const auto rows = py::ssize_t(values.size());
    return ownedArray(std::move(values), {rows, 2});
}
py::array moveToArray(std::vector<glm::vec3>&& values) {
    const auto rows = py::ssize_t(values.size());
    return ownedArray(std::move(values), {rows, 3});
}
py::array moveToArray(std::vector<glm::vec4>&& values) {
    const auto rows = py::ssize_t(values.size());
    return ownedArray(std::move(values), {rows, 4});
}

py::array viewOf(float* data, size_t rows, size_t width, py::handle owner) {
    static float empty = 0.0f;
    return py::array_t<float>({py::ssize_t(rows), py::ssize_t(width)}, rows ? data : &empty, owner);
}
py::array viewOf(uint32_t* data, size_t rows, size_t width, py::handle owner) {
    static uint32_t empty = 0;
    if (width == 1) return py::array_t<uint32_t>({py::ssize_t(rows)}, rows ? data : &empty, owner);
    return py::array_t<uint32_t>({py::ssize_t(rows), py::ssize_t(width)}, rows ? data : &empty,
                                 owner);
}

int requireThreads(int threads, const char* arg) {
    const std::string problem = sg::threadCountProblem(threads);
    if (!problem.empty()) {
        throw py::value_error(std::string(arg) + ": " + problem +
                              " (0 = all cores, 1 = this thread, up to 1024)");
    }
    return threads;
}

void throwUnknownName(const char* arg, const std::string& givenName,
                      std::initializer_list<const char*> names) {
    std::string msg = std::string(arg) + ": unknown value '" + givenName + "'; expected one of ";
    bool first = true;
    for (const char* n : names) {
        if (!first) msg += ", ";
        first = false;
        msg += n;
    }
    throw py::value_error(msg);
}

} // namespace sg::python
