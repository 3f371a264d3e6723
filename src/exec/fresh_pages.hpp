// facet exec: large scratch arrays in pages fresh from the system (zero already), of 2 MB where the
// system grants them. Used by the stages that fill tens of megabytes once (creased normals, the OBJ
// reader's copy of its file); not an allocator for small or long-lived data.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>

namespace facet::detail {

// Zeros not written again as value-initializing does, and a fault and a page cleared per 2 MB
// rather than per 4 KB (the 1M sphere's 32 MB of sums by position took 20 ms less to fault in).
// Small arrays from calloc. Aligned to cache lines. For types whose zero bits are their zero value.
template <class T>
class ZeroedArray {
public:
    explicit ZeroedArray(std::size_t n) : bytes_(n * sizeof(T) + k_huge) {
        if (bytes_ < 2 * k_huge) {
            raw_ = std::calloc(bytes_, 1);
            bytes_ = 0;  // not mapped here
            if (!raw_) throw std::bad_alloc();
            data_ = reinterpret_cast<T*>(align(raw_, 64));
            return;
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
        if (bytes_)
            munmap(raw_, bytes_);
        else
            std::free(raw_);  // null after a move
    }
    std::size_t bytes_;
    void* raw_;
    T* data_;
};

}  // namespace facet::detail
