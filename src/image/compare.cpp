// facet image: comparing two images (facet/compare.hpp): differences, PSNR, SSIM, the difference
// picture. Plain scalar code: it runs once per comparison, not per frame.
#include "facet/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "math/portable_log.hpp"

namespace facet {
namespace {

// Wang et al.'s constants for 8-bit data: C1 = (K1 L)^2, C2 = (K2 L)^2, 11x11 Gaussian, sigma 1.5.
constexpr double k_c1 = (0.01 * 255) * (0.01 * 255), k_c2 = (0.03 * 255) * (0.03 * 255);
constexpr int k_window = 11;
constexpr double k_sigma = 1.5;

std::array<double, k_window> gaussian_weights() {
    std::array<double, k_window> g{};
    double sum = 0;
    for (int i = 0; i < k_window; ++i) {
        const double d = i - k_window / 2;
        g[i] = std::exp(-d * d / (2 * k_sigma * k_sigma));
        sum += g[i];
    }
    for (double& w : g) w /= sum;  // separable: the 2-D window is g g^T, which sums to 1
    return g;
}

int component(Rgba8 p, int c) {
    const std::uint8_t v[4] = {p.r, p.g, p.b, p.a};
    return v[c];
}
double channel(const Image& img, std::size_t i, int c) { return component(img.pixels[i], c); }

// SSIM of one window's moments.
double ssim_of(double mu_a, double mu_b, double aa, double bb, double ab) {
    const double var_a = aa - mu_a * mu_a, var_b = bb - mu_b * mu_b, cov = ab - mu_a * mu_b;
    return ((2 * mu_a * mu_b + k_c1) * (2 * cov + k_c2)) / ((mu_a * mu_a + mu_b * mu_b + k_c1) * (var_a + var_b + k_c2));
}

// An image smaller than the window: the whole image as one window of uniform weights.
double global_ssim(const Image& a, const Image& b, int c) {
    const double n = static_cast<double>(a.pixels.size());
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const double x = channel(a, i, c), y = channel(b, i, c);
        sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
    }
    return ssim_of(sa / n, sb / n, saa / n, sbb / n, sab / n);
}

// Mean SSIM of channel c over every window wholly inside the image. The Gaussian is separable:
// each row is filtered horizontally once into a ring of the last k_window rows, and each output row
// sums the ring vertically, so memory stays a few rows whatever the image size.
double channel_ssim(const Image& a, const Image& b, int c) {
    const int w = a.width, h = a.height;
    if (w < k_window || h < k_window) return global_ssim(a, b, c);
    static const std::array<double, k_window> g = gaussian_weights();
    const int out_w = w - k_window + 1, out_h = h - k_window + 1;
    constexpr int k_moments = 5;  // a, b, a^2, b^2, ab
    std::vector<double> ring(static_cast<std::size_t>(k_window) * k_moments * out_w);
    auto row_of = [&](int y, int m) { return ring.data() + (static_cast<std::size_t>(y % k_window) * k_moments + m) * out_w; };
    auto filter_row = [&](int y) {
        for (int x = 0; x < out_w; ++x) {
            double m[k_moments] = {0, 0, 0, 0, 0};
            for (int k = 0; k < k_window; ++k) {
                const std::size_t i = static_cast<std::size_t>(y) * w + x + k;
                const double p = channel(a, i, c), q = channel(b, i, c);
                m[0] += g[k] * p, m[1] += g[k] * q, m[2] += g[k] * p * p, m[3] += g[k] * q * q, m[4] += g[k] * p * q;
            }
            for (int j = 0; j < k_moments; ++j) row_of(y, j)[x] = m[j];
        }
    };
    for (int y = 0; y < k_window - 1; ++y) filter_row(y);
    double total = 0;
    for (int y = 0; y < out_h; ++y) {
        filter_row(y + k_window - 1);
        for (int x = 0; x < out_w; ++x) {
            double m[k_moments] = {0, 0, 0, 0, 0};
            for (int k = 0; k < k_window; ++k)
                for (int j = 0; j < k_moments; ++j) m[j] += g[k] * row_of(y + k, j)[x];
            total += ssim_of(m[0], m[1], m[2], m[3], m[4]);
        }
    }
    return total / (static_cast<double>(out_w) * out_h);
}

bool has_transparency(const Image& img) {
    return std::any_of(img.pixels.begin(), img.pixels.end(), [](Rgba8 p) { return p.a != 255; });
}

std::string text(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

}  // namespace

ImageComparison compare_images(const Image& a, const Image& b, int tolerance) {
    ImageComparison c;
    c.width_a = a.width, c.height_a = a.height, c.width_b = b.width, c.height_b = b.height;
    c.tolerance = tolerance;
    if (!c.same_size()) return c;
    c.pixels = a.pixels.size();
    const int channels = has_transparency(a) || has_transparency(b) ? 4 : 3;
    double squared = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        bool differs = false;
        for (int k = 0; k < 4; ++k) {
            const int d = std::abs(component(a.pixels[i], k) - component(b.pixels[i], k));
            c.max_difference[k] = std::max(c.max_difference[k], d);
            differs |= d > tolerance;
            if (k < channels) squared += static_cast<double>(d) * d;
        }
        c.differing_pixels += differs;
    }
    const double mse = c.pixels == 0 ? 0 : squared / (static_cast<double>(c.pixels) * channels);
    c.psnr = mse == 0 ? std::numeric_limits<double>::infinity() : 10 * portable::log10(255.0 * 255.0 / mse);
    double ssim = 0;
    for (int k = 0; k < channels; ++k) ssim += c.pixels == 0 ? 1 : channel_ssim(a, b, k);
    c.ssim = ssim / channels;
    return c;
}

bool within_thresholds(const ImageComparison& c, const CompareThresholds& t, std::string* why) {
    auto fail = [&](std::string reason) {
        if (why) *why = std::move(reason);
        return false;
    };
    if (!c.same_size())
        return fail("sizes differ: " + std::to_string(c.width_a) + "x" + std::to_string(c.height_a) + " and " +
                    std::to_string(c.width_b) + "x" + std::to_string(c.height_b));
    if (t.check_pixels) {
        const std::size_t allowed = t.max_differing_fraction
                                        ? static_cast<std::size_t>(std::floor(*t.max_differing_fraction * c.pixels))
                                        : t.max_differing_pixels;
        if (c.differing_pixels > allowed)
            return fail(std::to_string(c.differing_pixels) + " pixels differ by more than " + std::to_string(c.tolerance) +
                        ", " + std::to_string(allowed) + " allowed");
    }
    if (t.min_ssim && !(c.ssim >= *t.min_ssim)) return fail("SSIM " + text("%.6f", c.ssim) + " < " + text("%g", *t.min_ssim));
    if (t.min_psnr && !(c.psnr >= *t.min_psnr))
        return fail("PSNR " + text("%.2f", c.psnr) + " dB < " + text("%g", *t.min_psnr) + " dB");
    if (why) why->clear();
    return true;
}

Image difference_image(const Image& a, const Image& b, int tolerance) {
    if (a.width != b.width || a.height != b.height)
        throw FacetError(Error{ErrorCode::invalid_argument, "difference_image: the images differ in size"});
    Image out{a.width, a.height, std::vector<Rgba8>(a.pixels.size())};
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const Rgba8 p = a.pixels[i], q = b.pixels[i];
        int d = 0;
        for (int k = 0; k < 4; ++k) d = std::max(d, std::abs(component(p, k) - component(q, k)));
        if (d > tolerance) {
            out.pixels[i] = {255, 0, 0, 255};
        } else if (d > 0) {
            out.pixels[i] = {150, 150, 0, 255};
        } else {
            // A's luma over black, lifted and compressed into 40..135: recognizable, and far
            // enough from red and yellow for the differences to stand out.
            const int luma = (77 * p.r + 150 * p.g + 29 * p.b) >> 8;
            const auto v = static_cast<std::uint8_t>(40 + luma * p.a / 255 * 3 / 8);
            out.pixels[i] = {v, v, v, 255};
        }
    }
    return out;
}

}  // namespace facet
