// The SIMD kernels against their scalar specification, on every ISA this CPU runs: coverage of
// random triangles of every size (from sub-pixel to the edge of the guard band, where the 32-bit
// form of the edge functions is tightest) must be the reference's bit for bit, and the ISA switch
// itself must do what it says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "facet/detail/front_end.hpp"
#include "facet/isa.hpp"
#include "setup/setup.hpp"

namespace {

using namespace facet;
using namespace facet::detail;

// Restores the default ISA when a test ends, whatever it selected.
struct IsaGuard {
    ~IsaGuard() { select_isa("best"); }
};

FrontEndParams params_for(int width, int height) {
    FrontEndParams p{};
    p.state.cull = CullMode::none;
    p.scissor = {0, 0, width, height};
    p.vp_x = 0, p.vp_y = 0, p.vp_w = static_cast<float>(width), p.vp_h = static_cast<float>(height);
    p.tile_size = 64;
    p.tiles_x = (width + 63) / 64, p.tiles_y = (height + 63) / 64;
    return p;
}

// A random triangle whose vertices lie within `extent` pixels of `centre` (fixed point).
void random_triangle(std::mt19937& rng, double centre_x, double centre_y, double extent, ScreenVertex (&v)[3]) {
    std::uniform_real_distribution<double> offset(-extent, extent);
    for (ScreenVertex& s : v) {
        const double x = std::clamp(centre_x + offset(rng), -16384.0, 16384.0);
        const double y = std::clamp(centre_y + offset(rng), -16384.0, 16384.0);
        s = {static_cast<std::int32_t>(std::lround(x * k_subpixel_one)),
             static_cast<std::int32_t>(std::lround(y * k_subpixel_one)), 0.5f, 1.0f};
    }
}

bool same_coverage(const TileCoverage& a, bool any_a, const TileCoverage& b, bool any_b) {
    if (any_a != any_b) return false;
    if (!any_a) return true;
    if (a.first_row != b.first_row || a.last_row != b.last_row) return false;
    for (int r = a.first_row; r <= a.last_row; ++r)
        if (a.rows[r] != b.rows[r]) return false;
    return true;
}

TEST(Isa, TheSwitchListsSelectsAndRestores) {
    IsaGuard guard;
    const std::vector<std::string> isas = available_isas();
    ASSERT_FALSE(isas.empty());
    EXPECT_EQ(isas.back(), "scalar");
    EXPECT_EQ(active_isa(), isas.front());
    for (const std::string& name : isas) {
        ASSERT_TRUE(select_isa(name)) << name;
        EXPECT_EQ(active_isa(), name);
    }
    EXPECT_FALSE(select_isa("altivec"));
    EXPECT_EQ(active_isa(), "scalar");  // a refused name changes nothing
    EXPECT_TRUE(select_isa("best"));
    EXPECT_EQ(active_isa(), isas.front());
}

TEST(Isa, CoverageOfRandomTrianglesEqualsTheScalarSpecificationOnEveryIsa) {
    IsaGuard guard;
    const int width = 8192, height = 8192;
    const FrontEndParams params = params_for(width, height);
    std::mt19937 rng(20261121);
    const double extents[] = {0.7, 3, 12, 40, 200, 3000, 16384};
    const int tile_sizes[] = {8, 16, 32, 64};
    const std::uint32_t refs[3] = {0, 1, 2};

    int compared = 0, covered = 0;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        std::mt19937 local(rng());
        for (int i = 0; i < 6000; ++i) {
            const double extent = extents[i % std::size(extents)];
            std::uniform_real_distribution<double> where(-64, width + 64);
            ScreenVertex v[3];
            random_triangle(local, where(local), where(local), extent, v);
            TriangleSetup t{};
            if (setup_triangle(v, refs, params, t) != SetupResult::ok) continue;
            // A few tiles of a random size that overlap the triangle's bounds.
            const int tile = tile_sizes[local() % std::size(tile_sizes)];
            for (int k = 0; k < 4; ++k) {
                std::uniform_int_distribution<int> tx(t.min_x / tile, t.max_x / tile), ty(t.min_y / tile, t.max_y / tile);
                const int x0 = tx(local) * tile, y0 = ty(local) * tile;
                const PixelRect rect{x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height)};
                TileCoverage simd{}, reference{};
                const bool any_simd = rasterize_tile(t, rect, simd);
                const bool any_reference = rasterize_tile_reference(t, rect, reference);
                ASSERT_TRUE(same_coverage(simd, any_simd, reference, any_reference))
                    << isa << ": triangle " << i << " (" << v[0].x << "," << v[0].y << ") (" << v[1].x << ","
                    << v[1].y << ") (" << v[2].x << "," << v[2].y << "), tile at " << x0 << "," << y0 << " size " << tile;
                ++compared;
                covered += any_reference;
            }
        }
    }
    // The comparison saw many tiles with coverage and many without.
    EXPECT_GT(covered, 5000);
    EXPECT_GT(compared - covered, 1000);
}

}  // namespace
