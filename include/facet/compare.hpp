// facet: comparing two images, for visual tests (`facet diff`, `facet render --reference`). In: two
// RGBA8 images. Out: their differences as numbers (size, per-channel largest absolute difference,
// how many pixels differ, PSNR, SSIM), whether they are within thresholds, and a picture of where
// they differ. It reads no files and knows nothing of the renderer.
//
// Thresholds default to "exact": facet's images are the same bytes whatever the thread count, ISA or
// machine, so any difference between two renders of one scene is a change. Other renderers differ
// in every anti-aliased edge; for those, compare by SSIM (structural similarity, Wang et al. 2004).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "facet/api.hpp"
#include "facet/error.hpp"
#include "facet/image.hpp"

FACET_API_BEGIN
namespace facet {

struct ImageComparison {
    int width_a = 0, height_a = 0, width_b = 0, height_b = 0;
    bool same_size() const { return width_a == width_b && height_a == height_b; }
    // The rest is meaningful only for images of the same size.
    std::array<int, 4> max_difference{};  // largest |a - b| per channel: R, G, B, A
    std::size_t differing_pixels = 0;     // pixels with some channel differing by more than the tolerance
    std::size_t pixels = 0;
    int tolerance = 0;  // the per-channel difference that does not count (CompareThresholds::tolerance)
    // Over R, G, B, and A when either image has a pixel that is not opaque: 10 log10(255^2 / MSE),
    // infinite for identical images.
    double psnr = 0;
    // Mean SSIM over the same channels: 11x11 Gaussian windows (sigma 1.5) lying wholly inside the
    // image, K1 = 0.01, K2 = 0.03, L = 255 (Wang et al.); an image smaller than the window is one
    // window of uniform weights. 1 for identical images.
    double ssim = 0;
};

struct CompareThresholds {
    int tolerance = 0;                       // per-channel difference (0..255) that is not a difference
    std::size_t max_differing_pixels = 0;    // pixels allowed to differ by more than `tolerance`
    std::optional<double> max_differing_fraction;  // instead, as a fraction of the pixels (0..1)
    std::optional<double> min_ssim;          // also require SSIM >= this
    std::optional<double> min_psnr;          // also require PSNR >= this (dB)
    bool check_pixels = true;                // false: only the SSIM and PSNR bounds apply
};

ImageComparison compare_images(const Image& a, const Image& b, int tolerance = 0);

// Whether `c` is within `t`; when not, `why` (if given) says which bound failed, e.g.
// "3 pixels differ by more than 0, 0 allowed" or "SSIM 0.912 < 0.95".
bool within_thresholds(const ImageComparison& c, const CompareThresholds& t, std::string* why = nullptr);

// Where two images of the same size differ: a dimmed grey copy of `a`, with the pixels that differ
// by more than `tolerance` in red and those that differ by at most it (but differ) in dark yellow.
// Opaque. Throws FacetError for images of different sizes.
Image difference_image(const Image& a, const Image& b, int tolerance = 0);

}  // namespace facet
FACET_API_END
