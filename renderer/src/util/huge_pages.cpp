#include "util/huge_pages.h"

#include <cstdint>

#include <sys/mman.h>
#include <unistd.h>

namespace rt::huge_pages {
namespace {

size_t small_page_bytes() {
    static const size_t bytes = size_t(sysconf(_SC_PAGESIZE));
    return bytes;
}

size_t round_up(size_t bytes, size_t to) { return (bytes + to - 1) / to * to; }

}  // namespace

void* allocate(size_t bytes) {
    // Map a huge page more than asked, then give back what lies before the
    // first boundary and after the end. The tail past the last whole huge
    // page stays in small pages rather than be rounded up to a whole one.
    const size_t length = round_up(bytes, small_page_bytes());
    const size_t padded = length + kPageBytes;
    void* raw = mmap(nullptr, padded, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) return nullptr;
    const uintptr_t start = reinterpret_cast<uintptr_t>(raw);
    const uintptr_t aligned = round_up(start, kPageBytes);
    if (aligned > start) munmap(raw, aligned - start);
    const uintptr_t end = aligned + length, raw_end = start + padded;
    if (raw_end > end) munmap(reinterpret_cast<void*>(end), raw_end - end);
#ifdef MADV_HUGEPAGE
    // Advice only: a kernel without THP leaves the pages small.
    madvise(reinterpret_cast<void*>(aligned), length, MADV_HUGEPAGE);
#endif
    return reinterpret_cast<void*>(aligned);
}

void release(void* p, size_t bytes) { munmap(p, round_up(bytes, small_page_bytes())); }

}  // namespace rt::huge_pages
