// facet exec: large scratch arrays in pages fresh from the system (zero already), of 2 MB where the
// system grants them. Used by the stages that fill tens of megabytes once (creased normals, the OBJ
// reader's copy of its file); not an allocator for small or long-lived data. And the heap's free top
// faulted in ahead of the stages that will carve it (populate_heap_top).
#pragma once

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <utility>

namespace facet::detail {

namespace fresh_detail {
// The mapping a ZeroedArray released inside a RecycleFreshPages scope on this thread keeps for the
// next one (raw == nullptr: none), and whether such a scope is open.
struct Recycled {
    void* raw = nullptr;
    std::size_t bytes = 0;
    int scopes = 0;
};
inline thread_local Recycled recycled;
}  // namespace fresh_detail

// Zeros not written again as value-initializing does, and a fault and a page cleared per 2 MB
// rather than per 4 KB (the 1M sphere's 32 MB of sums by position took 20 ms less to fault in).
// Small arrays from calloc. Aligned to cache lines. For types whose zero bits are their zero value.
template <class T>
class ZeroedArray {
public:
    ZeroedArray() = default;  // empty
    explicit ZeroedArray(std::size_t n) : bytes_(n * sizeof(T) + k_huge) {
        if (bytes_ < 2 * k_huge) {
            raw_ = std::calloc(n * sizeof(T) + 64, 1);
            bytes_ = 0;  // not mapped here
            if (!raw_) throw std::bad_alloc();
            data_ = reinterpret_cast<T*>(align(raw_, 64));
            return;
        }
        fresh_detail::Recycled& kept = fresh_detail::recycled;
        if (kept.raw && kept.bytes >= bytes_) {
            // Pages this thread touched a moment ago: cleared here, not faulted in anew.
            raw_ = std::exchange(kept.raw, nullptr);
            bytes_ = std::exchange(kept.bytes, 0);
            data_ = reinterpret_cast<T*>(align(raw_, k_huge));
            std::memset(static_cast<void*>(data_), 0, n * sizeof(T));
            return;
        }
        if (kept.raw) {
            // A larger array than the kept one: that mapping grown (its pages moved, not copied),
            // what was written there cleared, the rest fresh.
            void* grown = mremap(kept.raw, kept.bytes, bytes_, MREMAP_MAYMOVE);
            if (grown != MAP_FAILED) {
                const std::size_t written = std::exchange(kept.bytes, 0);
                kept.raw = nullptr;
                raw_ = grown;
                const std::uintptr_t start = align(raw_, k_huge);
                const std::size_t offset = start - reinterpret_cast<std::uintptr_t>(raw_);
                madvise(reinterpret_cast<void*>(start), bytes_ - offset, MADV_HUGEPAGE);
                data_ = reinterpret_cast<T*>(start);
                if (written > offset) std::memset(static_cast<void*>(data_), 0, std::min(n * sizeof(T), written - offset));
                return;
            }
        }
        raw_ = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw_ == MAP_FAILED) throw std::bad_alloc();
        const std::uintptr_t start = align(raw_, k_huge);
        madvise(reinterpret_cast<void*>(start), bytes_ - (start - reinterpret_cast<std::uintptr_t>(raw_)), MADV_HUGEPAGE);
        data_ = reinterpret_cast<T*>(start);
    }
    ~ZeroedArray() { release(); }
    ZeroedArray(ZeroedArray&& other) noexcept
        : bytes_(std::exchange(other.bytes_, 0)), raw_(std::exchange(other.raw_, nullptr)), data_(std::exchange(other.data_, nullptr)) {}
    ZeroedArray& operator=(ZeroedArray&& other) noexcept {
        if (this != &other) {
            release();
            bytes_ = std::exchange(other.bytes_, 0);
            raw_ = std::exchange(other.raw_, nullptr);
            data_ = std::exchange(other.data_, nullptr);
        }
        return *this;
    }
    ZeroedArray(const ZeroedArray&) = delete;
    ZeroedArray& operator=(const ZeroedArray&) = delete;
    T& operator[](std::size_t i) const { return data_[i]; }
    T* data() const { return data_; }

private:
    static constexpr std::uintptr_t k_huge = 2 << 20;
    static std::uintptr_t align(void* p, std::uintptr_t to) {
        return (reinterpret_cast<std::uintptr_t>(p) + to - 1) & ~(to - 1);
    }
    void release() {
        if (!bytes_) {
            std::free(raw_);  // null after a move
            return;
        }
        fresh_detail::Recycled& kept = fresh_detail::recycled;
        if (kept.scopes > 0 && bytes_ > kept.bytes) {
            // Kept for the next array, in place of a smaller one.
            if (kept.raw) munmap(kept.raw, kept.bytes);
            kept.raw = raw_;
            kept.bytes = bytes_;
        } else {
            munmap(raw_, bytes_);
        }
    }
    std::size_t bytes_ = 0;
    void* raw_ = nullptr;
    T* data_ = nullptr;
};

// While one is open on a thread, the largest mapping of a ZeroedArray released on that thread is
// kept (not unmapped) and the next ZeroedArray made there takes it, cleared by memset (grown by
// mremap if it is larger): for stages that free tens of megabytes (a file's text, the OBJ join's
// table) before the next maps as many (the creased normals' sums).
// Pages faulted in a moment ago are cleared faster than fresh ones are faulted in, and far faster on
// a VM that hands memory freed for a few seconds back to its host (docs/BENCHMARKS.md "Loading OBJ,
// session 12"). The last scope to close unmaps what is kept.
class RecycleFreshPages {
public:
    RecycleFreshPages() { ++fresh_detail::recycled.scopes; }
    ~RecycleFreshPages() {
        fresh_detail::Recycled& kept = fresh_detail::recycled;
        if (--kept.scopes == 0 && kept.raw) {
            munmap(kept.raw, kept.bytes);
            kept = {};
        }
    }
    RecycleFreshPages(const RecycleFreshPages&) = delete;
    RecycleFreshPages& operator=(const RecycleFreshPages&) = delete;
};

// Advises the system to back the whole 2 MiB pages inside [data, data + bytes) with 2 MiB pages
// when they are first touched: for a large array reserved once and filled (a std::vector's
// storage, which glibc maps fresh at these sizes), so that it is faulted in per 2 MiB, not per
// 4 KiB. Nothing for arrays under 4 MiB. Contents and results are unchanged either way.
inline void advise_huge_pages(const void* data, std::size_t bytes) {
    constexpr std::uintptr_t huge = 2 << 20;
    if (bytes < 2 * huge) return;
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(data) + huge - 1) & ~(huge - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(huge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

// A vector's capacity reserved for `n` elements, and advised as above.
template <class Vector>
void reserve_in_huge_pages(Vector& v, std::size_t n) {
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(*v.data()));
}

// Faults in the first `max_bytes` of the heap's free top (glibc's top chunk, where the next blocks
// are carved), a 2 MiB page at a time while go_on(), for a thread that would otherwise wait: the
// stages after it then find their memory mapped and cleared. MADV_POPULATE_WRITE writes nothing,
// so other threads may allocate from the heap meanwhile. Returns the bytes populated. Nothing where
// the kernel (before Linux 5.14) or the allocator (a sanitizer's) does not take part.
template <class GoOn>
std::size_t populate_heap_top(std::size_t max_bytes, const GoOn& go_on) {
    std::size_t done = 0;
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    constexpr std::uintptr_t page = 4096, huge = 2 << 20;
    const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
    const std::size_t free_top = mallinfo2().keepcost;
    if (free_top > end) return 0;
    const std::uintptr_t first = (end - free_top) & ~(page - 1);
    const std::uintptr_t last = first + std::min<std::size_t>(max_bytes, end - first);
    for (std::uintptr_t at = first; at < last && go_on();) {
        const std::uintptr_t next = std::min(last, (at + huge) & ~(huge - 1));
        if (madvise(reinterpret_cast<void*>(at), next - at, MADV_POPULATE_WRITE) != 0) break;
        done += next - at;
        at = next;
    }
#else
    (void)max_bytes;
    (void)go_on;
#endif
    return done;
}

}  // namespace facet::detail
