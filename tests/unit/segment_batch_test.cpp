// Line segments' records made in SIMD batches (setup_segment_lanes) against their specification,
// segment_record one segment at a time, on every ISA this CPU runs: the same records byte for byte
// (zero-initialised on both sides, so padding compares too), with the ends given or square ones the
// kernel makes (square_end), the same segments left as triangles
// (not strictly convex quads, edges past 32 bits) and the same ones dropped (empty bounds). Random
// segments of every length and direction with square ends of many widths, mitre-like and crossed
// offsets, ends on pixel centres (the top-left rule), the guard band's extremes, scissors that cut
// or leave nothing, partly filled batches, batches of square ends only (parallelograms: the kernel
// tests one turn), and coordinates past the kernel's exact range (it must decline the batch).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "facet/isa.hpp"
#include "raster/segment.hpp"
#include "support/pixels.hpp"

namespace {

using namespace facet;
using namespace facet::detail;

using facet_test::IsaGuard;

constexpr int k_guard = 16384 * k_subpixel_one;  // the guard band's extreme coordinate, fixed point

class Generator {
public:
    explicit Generator(std::uint32_t seed) : rng_(seed) {}

    std::int32_t coordinate(std::int32_t range) {
        return std::uniform_int_distribution<std::int32_t>(-range, range)(rng_);
    }
    int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }

    PixelRect scissor() {
        switch (pick(4)) {
            case 0: return {0, 0, 1920, 1080};
            case 1: return {0, 0, 8192, 8192};
            case 2: {
                const int x0 = pick(600), y0 = pick(600);
                return {x0, y0, x0 + 1 + pick(600), y0 + 1 + pick(600)};
            }
            default: return {100, 100, 100 + pick(2), 100 + pick(2)};  // empty or one pixel
        }
    }

    // One segment: its ends (distinct) and its ends' offsets. `wide`: past the exact range.
    void segment(ScreenVertex& a, ScreenVertex& b, SegmentEnd& e0, SegmentEnd& e1, bool wide) {
        do {
            ends(a, b, wide);
        } while (a.x == b.x && a.y == b.y);
        const double dx = b.x - a.x, dy = b.y - a.y, length = std::sqrt(dx * dx + dy * dy);
        const double widths[] = {1, 1, 1, 0.5, 1.5, 2, 3.7, 0.01, 64, 256};
        const double h = widths[pick(10)] / 2 * k_subpixel_one;
        const SegmentEnd square{static_cast<std::int32_t>(std::lround(-dy / length * h)),
                                static_cast<std::int32_t>(std::lround(dx / length * h))};
        e0 = e1 = square;
        switch (pick(6)) {
            case 0: e0 = {coordinate(4 * static_cast<int>(h) + 1), coordinate(4 * static_cast<int>(h) + 1)}; break;
            case 1: e1 = {coordinate(4 * static_cast<int>(h) + 1), coordinate(4 * static_cast<int>(h) + 1)}; break;
            case 2: e1 = {-square.ox, -square.oy}; break;  // crossed: not convex
            case 3: e0 = e1 = {0, 0}; break;              // no width
            default: break;
        }
    }
    std::uint32_t ref() { return static_cast<std::uint32_t>(rng_()); }

private:
    ScreenVertex vertex(std::int32_t x, std::int32_t y) {
        return {x, y, std::uniform_real_distribution<float>(0, 1)(rng_),
                std::uniform_real_distribution<float>(0.01f, 10)(rng_)};
    }
    void ends(ScreenVertex& a, ScreenVertex& b, bool wide) {
        if (wide) {
            a = vertex(coordinate(1 << 26), coordinate(1 << 26)), b = vertex(coordinate(1 << 26), coordinate(1 << 26));
            return;
        }
        switch (pick(5)) {
            case 0:  // anywhere in the guard band
                a = vertex(coordinate(k_guard), coordinate(k_guard)), b = vertex(coordinate(k_guard), coordinate(k_guard));
                break;
            case 1:  // on pixel centres and half-pixel steps
                a = vertex(128 * (coordinate(40) + 8), 128 * (coordinate(40) + 8));
                b = vertex(128 * (coordinate(40) + 8), 128 * (coordinate(40) + 8));
                break;
            case 2:  // the guard band's corners
                a = vertex(pick(2) ? k_guard : -k_guard, pick(2) ? k_guard : -k_guard);
                b = vertex(coordinate(k_guard), pick(2) ? k_guard : -k_guard);
                break;
            default: {  // a few pixels long on screen, as a wireframe's or the benchmark's
                const std::int32_t cx = coordinate(1000 * k_subpixel_one) + 960 * k_subpixel_one;
                const std::int32_t cy = coordinate(600 * k_subpixel_one) + 540 * k_subpixel_one;
                const std::int32_t r = pick(2) ? 2000 : 8 * k_subpixel_one;
                a = vertex(cx + coordinate(r), cy + coordinate(r)), b = vertex(cx + coordinate(r), cy + coordinate(r));
                break;
            }
        }
    }
    std::mt19937 rng_;
};

TEST(SegmentBatch, EveryIsaWritesTheRecordsOfSegmentRecord) {
    IsaGuard guard;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        Generator gen(2604);
        SegmentBatch batch{};
        SetupLanes lanes;
        std::size_t records = 0, triangles = 0, declined = 0, mismatches = 0;
        for (int round = 0; round < 4000; ++round) {
            const PixelRect scissor = gen.scissor();
            // Mostly full batches; some partly filled ones over stale lanes of earlier batches.
            batch.count = round % 5 == 0 ? 1 + gen.pick(SegmentBatch::k_capacity) : SegmentBatch::k_capacity;
            const bool wide = round % 97 == 0;
            const double widths[] = {1, 1.5, 0.25, 3, 255.5};
            batch.half_width = widths[round % 5] / 2;
            SegmentEnd ends[SegmentBatch::k_capacity][2];
            for (int i = 0; i < batch.count; ++i) {
                SegmentEnd e0, e1;
                gen.segment(batch.a[i], batch.b[i], e0, e1, wide && i == batch.count / 2);
                batch.ox0[i] = e0.ox, batch.oy0[i] = e0.oy, batch.ox1[i] = e1.ox, batch.oy1[i] = e1.oy;
                // Square ends: the kernel makes them, ignoring the offsets (every segment of a third of
                // the batches, as a line list's: the kernel's path for batches of parallelograms).
                batch.square[i] = round % 3 == 0 ? 1 : gen.pick(2);
                if (batch.square[i]) e0 = e1 = square_end(batch.a[i], batch.b[i], batch.half_width);
                ends[i][0] = e0, ends[i][1] = e1;
                batch.ref_a[i] = gen.ref(), batch.ref_b[i] = gen.ref();
            }
            if (!setup_segment_lanes(batch, scissor, lanes)) {
                ++declined;
                EXPECT_TRUE(wide || isa == "scalar") << isa << " round " << round;
                continue;
            }
            EXPECT_FALSE(wide) << isa << " round " << round;
            for (int i = 0; i < batch.count; ++i) {
                TriangleSetup want{};
                const SegmentResult r = segment_record(batch.a[i], batch.b[i], ends[i][0], ends[i][1], batch.ref_a[i],
                                                       batch.ref_b[i], scissor, want);
                const bool kept = lanes.keep >> i & 1, left = lanes.culled >> i & 1;
                ASSERT_EQ(kept, r == SegmentResult::record) << isa << " round " << round << " segment " << i;
                ASSERT_EQ(left, r == SegmentResult::triangles) << isa << " round " << round << " segment " << i;
                if (!kept) {
                    triangles += left;
                    continue;
                }
                TriangleSetup got{};
                write_record(lanes, i, got);
                mismatches += std::memcmp(&got, &want, sizeof got) != 0;
                ++records;
            }
            EXPECT_EQ(lanes.keep >> batch.count, 0u) << isa << " round " << round;  // no lane past the count
            EXPECT_EQ(lanes.culled >> batch.count, 0u) << isa << " round " << round;
        }
        EXPECT_EQ(mismatches, 0u) << isa;
        if (isa == "scalar") continue;
        EXPECT_GT(records, 5000u) << isa;    // the comparison saw many records,
        EXPECT_GT(triangles, 2000u) << isa;  // many quads left as triangles,
        EXPECT_GT(declined, 20u) << isa;     // and batches past the exact range
    }
}

}  // namespace
