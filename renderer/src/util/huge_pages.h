// Memory for the large arrays that ray queries read at random: the wide BVH's
// nodes and its triangle blocks. An incoherent ray touches a few dozen cache
// lines scattered over tens of megabytes, and in 4 KiB pages nearly each one
// is also a TLB miss: dragon_1's 45 MB span 11,000 pages, against the 3,072
// entries of a Zen 4 core's second-level TLB. In 2 MiB pages they span 23.
//
// So arrays of a huge page or more are mapped on a 2 MiB boundary and
// advised as transparent huge pages before their first touch, which is when
// the kernel picks the page size. Embree does the same with its BVH
// (os_malloc then os_advise, common/sys/alloc.cpp), so the comparison in
// bvh_bench is even. Where the kernel gives none (THP "never") this is an
// ordinary mapping; smaller arrays come from operator new.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace rt {

namespace huge_pages {
inline constexpr size_t kPageBytes = size_t(2) << 20;
// Under AddressSanitizer every array comes from operator new, whose redzones
// catch the overflows a mapping of our own would hide.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kMapsArrays = false;
#else
inline constexpr bool kMapsArrays = true;
#endif
// Whether an array of `bytes` is mapped apart (allocate) and so unmapped (release).
inline bool mapped(size_t bytes) { return kMapsArrays && bytes >= kPageBytes; }
// A mapping of at least `bytes` on a kPageBytes boundary, advised as huge
// pages, or nullptr when the system refuses it.
void* allocate(size_t bytes);
void release(void* p, size_t bytes);
}  // namespace huge_pages

template <typename T>
struct HugePageAllocator {
    using value_type = T;

    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U>&) {}

    T* allocate(size_t n) {
        const size_t bytes = n * sizeof(T);
        if (!huge_pages::mapped(bytes)) return static_cast<T*>(::operator new(bytes, std::align_val_t{alignof(T)}));
        if (void* p = huge_pages::allocate(bytes)) return static_cast<T*>(p);
        throw std::bad_alloc();
    }
    void deallocate(T* p, size_t n) {
        const size_t bytes = n * sizeof(T);
        if (huge_pages::mapped(bytes))
            huge_pages::release(p, bytes);
        else
            ::operator delete(p, std::align_val_t{alignof(T)});
    }

    template <typename U>
    bool operator==(const HugePageAllocator<U>&) const { return true; }
};

template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace rt
