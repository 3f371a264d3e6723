// facet benchmarks: JPEG decoding, stb_image (what facet's textures used) against libjpeg-turbo's
// TurboJPEG API as Texture::decode now calls it (accurate integer IDCT, fancy upsampling, stop on
// warnings), on the files given.
// Not a stage of the renderer. For each file: whether both give the same RGBA pixels (how many
// differ, by at most how much) and the median decode time of each.
// Usage: facet_bench_jpeg [--rounds N] FILE...
#include <turbojpeg.h>

#include <stb_image.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = 5;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help") {
            std::printf("usage: facet_bench_jpeg [--rounds N] FILE...\nDecodes each JPEG with stb_image and with libjpeg-turbo: "
                        "pixels compared, median times.\n");
            return 0;
        }
        if (a == "--rounds" && i + 1 < argc) {
            rounds = std::max(1, std::atoi(argv[++i]));
            continue;
        }
        files.push_back(a);
    }
    if (files.empty()) {
        std::fprintf(stderr, "usage: facet_bench_jpeg [--rounds N] FILE...\n");
        return 2;
    }
    int status = 0;
    tjhandle tj = tjInitDecompress();
    for (const std::string& file : files) {
        std::ifstream in(file, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        std::vector<double> stb_ms, turbo_ms;
        std::vector<unsigned char> stb_pixels, turbo_pixels;
        int w = 0, h = 0;
        for (int r = 0; r < rounds; ++r) {
            Clock::time_point start = Clock::now();
            int channels = 0;
            stbi_uc* p = stbi_load_from_memory(data, static_cast<int>(bytes.size()), &w, &h, &channels, 4);
            stb_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
            if (!p) break;
            stb_pixels.assign(p, p + static_cast<std::size_t>(w) * h * 4);
            stbi_image_free(p);

            start = Clock::now();
            int tw = 0, th = 0, sub = 0, space = 0;
            bool ok = tjDecompressHeader3(tj, data, bytes.size(), &tw, &th, &sub, &space) == 0;
            turbo_pixels.resize(static_cast<std::size_t>(tw) * th * 4);
            ok = ok && tjDecompress2(tj, data, bytes.size(), turbo_pixels.data(), tw, 0, th, TJPF_RGBA, TJFLAG_ACCURATEDCT | TJFLAG_STOPONWARNING) == 0;
            turbo_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
            if (!ok || tw != w || th != h) turbo_pixels.clear();
        }
        if (stb_pixels.empty() || turbo_pixels.size() != stb_pixels.size()) {
            std::printf("%s: not decoded by both\n", file.c_str());
            status = 1;
            continue;
        }
        std::size_t differ = 0;
        int worst = 0;
        for (std::size_t i = 0; i < stb_pixels.size(); ++i) {
            const int d = std::abs(int(stb_pixels[i]) - int(turbo_pixels[i]));
            differ += d != 0;
            worst = std::max(worst, d);
        }
        std::printf("%s: %dx%d, %zu of %zu channel values differ (at most by %d); stb_image %.2f ms, libjpeg-turbo %.2f ms (%.2fx)\n",
                    file.c_str(), w, h, differ, stb_pixels.size(), worst, median(stb_ms), median(turbo_ms),
                    median(stb_ms) / median(turbo_ms));
    }
    tjDestroy(tj);
    return status;
}
