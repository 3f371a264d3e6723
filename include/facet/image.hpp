// facet: pixels. Image is plain RGBA8 data (what PNG files hold); Framebuffer is the render target:
// RGBA8 colour plus a float depth buffer, row-major, first row at the top of the picture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "facet/api.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {

struct Rgba8 {
    std::uint8_t r = 0, g = 0, b = 0, a = 0;
    friend constexpr bool operator==(Rgba8, Rgba8) = default;
};

// Converts a colour in [0, 1] to 8 bits per channel with rounding; out-of-range values are clamped
// and NaN becomes 0, so no shader can write garbage.
inline Rgba8 to_rgba8(Vec4 c) {
    auto q = [](float v) -> std::uint8_t {
        v = v > 0 ? v : 0;  // also maps NaN to 0
        v = v < 1 ? v : 1;
        return static_cast<std::uint8_t>(v * 255.0f + 0.5f);
    };
    return {q(c.x), q(c.y), q(c.z), q(c.w)};
}

inline Vec4 to_vec4(Rgba8 c) { return Vec4{c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, c.a / 255.0f}; }

struct Image {
    int width = 0, height = 0;
    std::vector<Rgba8> pixels;  // width * height, row-major, top row first
    Rgba8& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
    Rgba8 at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

// The largest width or height of a render target. Bounded so that snapped screen coordinates, with
// the guard band around the viewport, fit in 24 bits (8 of them sub-pixel): see the rasterizer's
// fixed-point notes in docs/architecture.md.
constexpr int k_max_target_size = 8192;

namespace detail {
// Allocates on 64-byte boundaries, so that a framebuffer's rows can be written in whole cache lines.
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    static constexpr std::align_val_t k_alignment{64};
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), k_alignment)); }
    void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, k_alignment); }
    friend bool operator==(const CacheLineAllocator&, const CacheLineAllocator&) { return true; }
};

// An allocator like Base<T> whose resize() leaves new elements as the memory holds them, so that
// an array can be sized ahead and each element written once, in place, by the stage that fills it.
// For trivial types that is not even a member's default initialiser (Vec4's zeros): the storage is
// the object.
template <template <class> class Base, class T>
struct LeftUninitialised : Base<T> {
    template <class U>
    struct rebind {
        using other = LeftUninitialised<Base, U>;
    };
    LeftUninitialised() = default;
    template <class U>
    LeftUninitialised(const LeftUninitialised<Base, U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        if constexpr (!(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>)) ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
template <class T>
using UninitialisedAllocator = LeftUninitialised<std::allocator, T>;
template <class T>
using UninitialisedCacheLineAllocator = LeftUninitialised<CacheLineAllocator, T>;
}  // namespace detail

class Framebuffer {
public:
    // Throws FacetError unless 1 <= width, height <= k_max_target_size. The colour starts at 0, the
    // depth at 1.
    Framebuffer(int width, int height);
    // Draws into width * height Rgba8 of the caller's memory from the start, as use_colour_memory
    // after the constructor above, but without making an array of its own and clearing anything:
    // the colour is the caller's memory as it is, the depth undefined until a clear (render_scene
    // and a draw with DrawState::clear clear both). For a target that is drawn into at once.
    // nullptr: memory of its own.
    Framebuffer(int width, int height, Rgba8* colour);

    int width() const { return width_; }
    int height() const { return height_; }

    void clear(Vec4 colour, float depth = 1.0f);
    void clear_colour(Vec4 colour);
    void clear_depth(float depth = 1.0f);

    // Makes the colour pixels width * height Rgba8 of the caller's memory (which must stay alive
    // while it is drawn into or read), so a draw writes straight into an array the caller hands on
    // (the Python package's NumPy arrays) instead of into the framebuffer's own, which is freed;
    // nullptr goes back to memory of its own (contents undefined). A copy of the framebuffer
    // shares the caller's memory. Rows that are 64-byte aligned are written fastest.
    void use_colour_memory(Rgba8* pixels);

    Rgba8* colour_data() { return external_colour_ ? external_colour_ : colour_.data(); }
    const Rgba8* colour_data() const { return external_colour_ ? external_colour_ : colour_.data(); }
    float* depth_data() { return depth_.data(); }
    const float* depth_data() const { return depth_.data(); }

    Rgba8 colour(int x, int y) const { return colour_data()[index(x, y)]; }
    float depth(int x, int y) const { return depth_[index(x, y)]; }

    Image to_image() const { return Image{width_, height_, {colour_data(), colour_data() + pixel_count()}}; }

private:
    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }
    std::size_t pixel_count() const { return static_cast<std::size_t>(width_) * height_; }
    int width_, height_;
    std::vector<Rgba8, detail::CacheLineAllocator<Rgba8>> colour_;
    Rgba8* external_colour_ = nullptr;  // use_colour_memory's; colour_ is empty then
    std::vector<float, detail::UninitialisedCacheLineAllocator<float>> depth_;
};

}  // namespace facet
FACET_API_END
