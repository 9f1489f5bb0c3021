// Scratch vectors for the long jobs (the MikkTSpace generator's buffers,
// the OBJ reader's blocks, the feature bake's grids): what makes a first
// call cost close to a warm one.
//
//  - No zero fill: resize() default-initializes new elements (for the
//    trivial types used here: leaves them indeterminate), so a buffer that
//    a step writes before it reads is touched once, by that step (in
//    parallel where the step is parallel), and pages of a buffer that is
//    only written sparsely are never touched at all. Code using these
//    vectors must write every element it reads (assign() or fill where it
//    relies on zeros), as it must anyway when a buffer is reused.
//  - Large blocks (>= kHugePageMinBytes) come straight from the operating
//    system, 2 MiB-aligned, with transparent huge pages requested
//    (madvise(MADV_HUGEPAGE), Linux; elsewhere, and under AddressSanitizer
//    so that it sees every block, the ordinary allocator):
//    the first touch then faults 2 MiB pages instead of 4 KiB ones. On a
//    virtual machine where a 4 KiB fault costs ~20-30 us this is most of
//    a first call's extra time (touching 128 MiB: ~600 ms with 4 KiB
//    pages, ~25 ms with huge pages, measured on the 2-core reference VM).
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace sg::detail {

inline constexpr size_t kHugePageBytes = size_t(2) << 20;
inline constexpr size_t kHugePageMinBytes = size_t(4) << 20;

// `bytes` (aligned to `alignment`, at most 4096) from the operating system
// with huge pages requested when bytes >= kHugePageMinBytes, else from
// operator new. Throws std::bad_alloc.
void* scratchAllocate(size_t bytes, size_t alignment);
// Frees what scratchAllocate(bytes, alignment) returned.
void scratchFree(void* p, size_t bytes, size_t alignment) noexcept;
// Asks for transparent huge pages on the 2 MiB-aligned pages inside
// [p, p + bytes) (memory this process owns and has not touched yet, e.g. a
// std::vector's fresh storage before it is filled). A hint only: no effect
// where unsupported or for fewer than kHugePageMinBytes.
void adviseHugePages(void* p, size_t bytes) noexcept;

template <class T>
struct ScratchAllocator {
    using value_type = T;
    ScratchAllocator() = default;
    template <class U>
    ScratchAllocator(const ScratchAllocator<U>&) noexcept {} // NOLINT: rebinding
    T* allocate(size_t n) { return static_cast<T*>(scratchAllocate(n * sizeof(T), alignof(T))); }
    void deallocate(T* p, size_t n) noexcept { scratchFree(p, n * sizeof(T), alignof(T)); }
    // resize(n): default-initialization, not value-initialization.
    template <class U>
    void construct(U* p) noexcept(noexcept(::new (static_cast<void*>(p)) U)) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    friend bool operator==(const ScratchAllocator&, const ScratchAllocator&) { return true; }
};

template <class T>
using ScratchVector = std::vector<T, ScratchAllocator<T>>;

// Grows `v` (a std::vector with the standard allocator, e.g. a caller's
// output) to capacity >= n with huge pages requested on fresh storage
// before anything touches it; the contents are kept.
template <class T>
void reserveWithHugePages(std::vector<T>& v, size_t n) {
    if (v.capacity() >= n) return;
    std::vector<T> grown;
    grown.reserve(n);
    adviseHugePages(grown.data(), n * sizeof(T));
    grown.insert(grown.end(), v.begin(), v.end());
    v.swap(grown);
}

// v = n copies of `value`, like v.assign(n, value); storage too small for
// n is replaced (not grown: the contents are overwritten anyway) by fresh
// storage with huge pages requested before the fill touches it.
template <class T>
void assignWithHugePages(std::vector<T>& v, size_t n, const T& value) {
    if (v.capacity() < n) {
        std::vector<T>().swap(v);
        v.reserve(n);
        adviseHugePages(v.data(), n * sizeof(T));
    }
    v.assign(n, value);
}

} // namespace sg::detail
