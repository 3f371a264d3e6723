// facet benchmarks: facet's PNG encoder (write_png: row blocks deflated in parallel) against libspng
// encoding the same image as facet did before (zlib level 2, the Up filter on every row, RGB for an
// opaque image, one stream on one thread), in one run: median wall ms over rounds, and the sizes.
// Not a stage of the renderer.
// Usage: facet_bench_png IMAGE.png [ROUNDS=20]   (e.g. a facet render of the bunny at 512x512)
#include <spng.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "facet/io.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// The encoder facet used before: libspng, level 2, Up, RGB rows packed one at a time.
std::size_t spng_encode(const facet::Image& image) {
    std::unique_ptr<spng_ctx, void (*)(spng_ctx*)> ctx(spng_ctx_new(SPNG_CTX_ENCODER), &spng_ctx_free);
    spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
    spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, 2);
    spng_set_option(ctx.get(), SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_UP);
    spng_ihdr ihdr{};
    ihdr.width = static_cast<std::uint32_t>(image.width);
    ihdr.height = static_cast<std::uint32_t>(image.height);
    ihdr.bit_depth = 8;
    ihdr.color_type = SPNG_COLOR_TYPE_TRUECOLOR;
    int err = spng_set_ihdr(ctx.get(), &ihdr);
    if (!err) err = spng_encode_image(ctx.get(), nullptr, 0, SPNG_FMT_PNG, SPNG_ENCODE_PROGRESSIVE | SPNG_ENCODE_FINALIZE);
    const auto width = static_cast<std::size_t>(image.width);
    std::vector<unsigned char> rgb(width * 3);
    for (std::uint32_t y = 0; !err && y < ihdr.height; ++y) {
        for (std::size_t x = 0; x < width; ++x) {
            const facet::Rgba8 p = image.pixels[y * width + x];
            rgb[3 * x] = p.r, rgb[3 * x + 1] = p.g, rgb[3 * x + 2] = p.b;
        }
        err = spng_encode_row(ctx.get(), rgb.data(), rgb.size());
        if (err == SPNG_EOI && y + 1 == ihdr.height) err = 0;
    }
    std::size_t size = 0;
    void* png = err ? nullptr : spng_get_png_buffer(ctx.get(), &size, &err);
    std::free(png);
    return err ? 0 : size;
}

template <class F>
double median_ms(int rounds, const F& f) {
    std::vector<double> ms;
    for (int r = 0; r < rounds; ++r) {
        const Clock::time_point start = Clock::now();
        f();
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3 || std::string(argv[1]) == "--help") {
        std::printf("usage: facet_bench_png IMAGE.png [ROUNDS=20]\n"
                    "Encodes the image (made opaque) with write_png at 1 and 2 threads and with libspng as facet did\n"
                    "before (level 2, Up, one thread), alternating; prints median wall ms and the sizes.\n");
        return argc == 2 ? 0 : 2;
    }
    facet::Result<facet::Image> read = facet::read_png(argv[1]);
    if (!read) {
        std::fprintf(stderr, "facet_bench_png: %s\n", read.error().message.c_str());
        return 1;
    }
    facet::Image image = std::move(*read);
    for (facet::Rgba8& p : image.pixels) p.a = 255;
    const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 20;
    const std::string out = "/tmp/facet_bench_png_out.png";
    std::size_t spng_size = 0;
    double spng_ms = 0, one_ms = 0, two_ms = 0;
    for (int pass = 0; pass < 2; ++pass) {  // the first pass warms up
        spng_ms = median_ms(rounds, [&] { spng_size = spng_encode(image); });
        one_ms = median_ms(rounds, [&] { (void)facet::write_png(out, image, {.threads = 1}); });
        two_ms = median_ms(rounds, [&] { (void)facet::write_png(out, image, {.threads = 2}); });
    }
    std::FILE* f = std::fopen(out.c_str(), "rb");
    long facet_size = 0;
    if (f && std::fseek(f, 0, SEEK_END) == 0) facet_size = std::ftell(f);
    if (f) std::fclose(f);
    std::printf("{\"width\":%d,\"height\":%d,\"rounds\":%d,\"libspng_ms\":%.2f,\"facet_1_thread_ms\":%.2f,"
                "\"facet_2_threads_ms\":%.2f,\"libspng_bytes\":%zu,\"facet_bytes\":%ld}\n",
                image.width, image.height, rounds, spng_ms, one_ms, two_ms, spng_size, facet_size);
}
