// Scratch buffers (scratch_buffer.h): large blocks mapped from the
// operating system, 2 MiB-aligned, with transparent huge pages requested.
#include "surfgrad/base/scratch_buffer.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

// Under AddressSanitizer every block comes from operator new, so that ASan
// sees it (overflows, use after free, the max_allocation_size_mb limit the
// memory tests of a sanitizer build rely on).
#if defined(__SANITIZE_ADDRESS__)
#define SG_SCRATCH_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SG_SCRATCH_ASAN 1
#endif
#endif
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(SG_SCRATCH_ASAN)
#define SG_SCRATCH_OS_PAGES 1
#endif

namespace sg::detail {

namespace {

size_t roundUp(size_t bytes, size_t to) {
    return (bytes + to - 1) / to * to;
}

} // namespace

void* scratchAllocate(size_t bytes, size_t alignment) {
#if defined(SG_SCRATCH_OS_PAGES)
    if (bytes >= kHugePageMinBytes) {
        // Map one huge page more than needed and unmap the unaligned head
        // and the tail, leaving a 2 MiB-aligned block.
        const size_t size = roundUp(bytes, kHugePageBytes);
        void* raw = mmap(nullptr, size + kHugePageBytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        const uintptr_t start = reinterpret_cast<uintptr_t>(raw);
        const uintptr_t aligned = roundUp(start, kHugePageBytes);
        if (aligned > start) munmap(raw, aligned - start);
        const uintptr_t end = start + size + kHugePageBytes;
        if (end > aligned + size)
            munmap(reinterpret_cast<void*>(aligned + size), end - aligned - size);
        void* p = reinterpret_cast<void*>(aligned);
        madvise(p, size, MADV_HUGEPAGE); // a hint: without THP, 4 KiB pages
        return p;
    }
#endif
    return ::operator new(bytes, std::align_val_t(alignment));
}

void scratchFree(void* p, size_t bytes, size_t alignment) noexcept {
    if (!p) return;
#if defined(SG_SCRATCH_OS_PAGES)
    if (bytes >= kHugePageMinBytes) {
        munmap(p, roundUp(bytes, kHugePageBytes));
        return;
    }
#else
    (void)bytes;
#endif
    ::operator delete(p, std::align_val_t(alignment));
}

void adviseHugePages(void* p, size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < kHugePageMinBytes) return;
    const uintptr_t start = roundUp(reinterpret_cast<uintptr_t>(p), kHugePageBytes);
    const uintptr_t end =
        (reinterpret_cast<uintptr_t>(p) + bytes) / kHugePageBytes * kHugePageBytes;
    if (end > start) madvise(reinterpret_cast<void*>(start), end - start, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

} // namespace sg::detail
