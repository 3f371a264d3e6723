// PNG files and atomic writes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "facet/io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;

fs::path temp_dir(const char* name) {
    fs::path d = fs::temp_directory_path() / ("facet_io_test_" + std::string(name));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

Image gradient(int w, int h) {
    Image img{w, h, std::vector<Rgba8>(static_cast<std::size_t>(w) * h)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.at(x, y) = {static_cast<std::uint8_t>(x * 7), static_cast<std::uint8_t>(y * 13),
                            static_cast<std::uint8_t>(x ^ y), static_cast<std::uint8_t>(255 - x)};
    return img;
}

TEST(Png, RoundTripIsLossless) {
    const fs::path dir = temp_dir("roundtrip");
    const Image img = gradient(37, 23);
    ASSERT_TRUE(write_png((dir / "a.png").string(), img).ok());
    Result<Image> back = read_png((dir / "a.png").string());
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 37);
    EXPECT_EQ(back->height, 23);
    EXPECT_TRUE(back->pixels == img.pixels);
}

// The colour type in the file's IHDR chunk (byte 25: signature 8, chunk length 4, "IHDR" 4,
// width 4, height 4, bit depth 1).
int png_colour_type(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    char header[26] = {};
    in.read(header, sizeof(header));
    return in ? static_cast<unsigned char>(header[25]) : -1;
}

TEST(Png, OpaqueImagesAreWrittenAsRgbAndOthersKeepTheirAlpha) {
    const fs::path dir = temp_dir("opaque");
    Image img = gradient(29, 17);
    for (Rgba8& p : img.pixels) p.a = 255;
    ASSERT_TRUE(write_png((dir / "rgb.png").string(), img).ok());
    EXPECT_EQ(png_colour_type(dir / "rgb.png"), 2);  // truecolour
    Result<Image> back = read_png((dir / "rgb.png").string());
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(back->pixels == img.pixels);

    img.at(28, 16).a = 254;  // one pixel short of opaque, the last one looked at
    ASSERT_TRUE(write_png((dir / "rgba.png").string(), img).ok());
    EXPECT_EQ(png_colour_type(dir / "rgba.png"), 6);  // truecolour with alpha
    back = read_png((dir / "rgba.png").string());
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(back->pixels == img.pixels);
}

TEST(Png, Gray16StoresBigEndianSamples) {
    const fs::path dir = temp_dir("gray16");
    const std::string path = (dir / "d.png").string();
    ASSERT_TRUE(write_png_gray16(path, 2, 1, {0x1234, 0xffff}).ok());
    // Decoded to RGBA8, 16-bit samples keep their high byte.
    Result<Image> back = read_png(path);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->at(0, 0).r, 0x12);
    EXPECT_EQ(back->at(1, 0).r, 0xff);
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Pixels that compress poorly (a hash of x and y), so that each block of rows holds real work.
Image noise(int w, int h, bool opaque) {
    Image img{w, h, std::vector<Rgba8>(static_cast<std::size_t>(w) * h)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::uint32_t v = (static_cast<std::uint32_t>(x) * 73856093u) ^ (static_cast<std::uint32_t>(y) * 19349663u);
            const std::uint32_t m = v * 2654435761u;
            img.at(x, y) = {static_cast<std::uint8_t>(m >> 24), static_cast<std::uint8_t>(m >> 16),
                            static_cast<std::uint8_t>(x + y), static_cast<std::uint8_t>(opaque ? 255 : m >> 8)};
        }
    return img;
}

// The encoder deflates blocks of rows (~128 KB of filtered bytes each) in parallel: a 200x400 image
// has 2 blocks as RGB and 3 as RGBA. The file must decode to the same pixels (libspng checks the
// chunks' CRCs and the zlib stream's Adler-32) and be the same bytes whatever the thread count.
TEST(Png, ImagesOfManyRowBlocksRoundTripInTheSameBytesOnAnyThreadCount) {
    const fs::path dir = temp_dir("blocks");
    for (bool opaque : {true, false}) {
        const Image img = noise(200, 400, opaque);
        std::string first;
        for (int threads : {1, 2, 3}) {
            const fs::path path = dir / ("t" + std::to_string(threads) + (opaque ? "rgb" : "rgba") + ".png");
            ASSERT_TRUE(write_png(path.string(), img, {.threads = threads}).ok());
            if (first.empty()) {
                first = file_bytes(path);
                EXPECT_EQ(png_colour_type(path), opaque ? 2 : 6);
                Result<Image> back = read_png(path.string());
                ASSERT_TRUE(back.ok()) << back.error().message;
                EXPECT_TRUE(back->pixels == img.pixels);
            } else {
                EXPECT_EQ(file_bytes(path), first) << threads << " threads";
            }
        }
    }
}

// With runs only, a block's dictionary is the byte before it: runs of a plain image cross the
// seams of its first blocks (a 256x512 RGBA image: 5 blocks of 127 rows), and each of those blocks'
// first run reaches back into it.
TEST(Png, RunsOnlyAcrossRowBlocksDecodeToTheSamePixelsOnAnyThreadCount) {
    const fs::path dir = temp_dir("runs");
    Image img{256, 512, std::vector<Rgba8>(256u * 512u, Rgba8{30, 40, 50, 200})};
    for (int y = 300; y < 512; ++y)
        for (int x = 0; x < 256; ++x) img.at(x, y) = {static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), 7, 255};
    std::string first;
    for (int threads : {1, 2}) {
        const fs::path path = dir / ("r" + std::to_string(threads) + ".png");
        ASSERT_TRUE(write_png(path.string(), img, {.threads = threads, .runs_only = true}).ok());
        Result<Image> back = read_png(path.string());
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_TRUE(back->pixels == img.pixels);
        if (first.empty()) first = file_bytes(path);
        else EXPECT_EQ(file_bytes(path), first);
    }
}

TEST(Png, EveryLevelDecodesToTheSamePixelsAndOthersAreRefused) {
    const fs::path dir = temp_dir("levels");
    const Image img = noise(100, 300, false);
    std::size_t stored = 0, best = 0;
    for (int level : {0, 1, 2, 6, 9}) {
        const fs::path path = dir / ("l" + std::to_string(level) + ".png");
        ASSERT_TRUE(write_png(path.string(), img, {.level = level}).ok());
        Result<Image> back = read_png(path.string());
        ASSERT_TRUE(back.ok()) << level << ": " << back.error().message;
        EXPECT_TRUE(back->pixels == img.pixels) << level;
        (level == 0 ? stored : best) = fs::file_size(path);
    }
    EXPECT_GT(stored, img.pixels.size() * 4);  // level 0 stores the filtered rows as they are
    EXPECT_LT(best, stored);
    for (int level : {-1, 10}) {
        const Status s = write_png((dir / "bad.png").string(), img, {.level = level});
        ASSERT_FALSE(s.ok());
        EXPECT_EQ(s.error().code, ErrorCode::invalid_argument);
        EXPECT_NE(s.error().message.find("bad.png"), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

TEST(Png, Rgb16OfManyRowBlocksKeepsEverySample) {
    const fs::path dir = temp_dir("rgb16");
    const int w = 200, h = 300;  // 1201 bytes a row: 3 blocks
    std::vector<std::uint16_t> values(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::uint16_t>(i * 40503u);
    const std::string path = (dir / "c.png").string();
    ASSERT_TRUE(write_png_rgb16(path, w, h, values).ok());
    Result<Image> back = read_png(path);  // 16-bit samples decode to their high byte
    ASSERT_TRUE(back.ok()) << back.error().message;
    for (std::size_t p = 0; p < back->pixels.size(); ++p) {
        const Rgba8 px = back->pixels[p];
        ASSERT_EQ(px.r, values[3 * p] >> 8) << p;
        ASSERT_EQ(px.g, values[3 * p + 1] >> 8) << p;
        ASSERT_EQ(px.b, values[3 * p + 2] >> 8) << p;
    }
}

TEST(Png, WritingIntoAMissingDirectoryFailsAndNamesTheFile) {
    const std::string path = "/nonexistent-dir-for-facet/x.png";
    const Status s = write_png(path, gradient(4, 4));
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, ErrorCode::io);
    EXPECT_NE(s.error().message.find(path), std::string::npos);
}

// facet render writes its frame from memory that is not an Image's: the same file, RGB or RGBA.
TEST(Png, PixelsInMemoryWriteTheSameFileAsTheirImage) {
    const fs::path dir = temp_dir("pointer");
    for (bool opaque : {true, false}) {
        const Image img = noise(64, 40, opaque);
        const fs::path from_image = dir / "image.png", from_memory = dir / "memory.png";
        ASSERT_TRUE(write_png(from_image.string(), img, {.threads = 2}).ok());
        ASSERT_TRUE(write_png(from_memory.string(), img.width, img.height, img.pixels.data(), {.threads = 2}).ok());
        EXPECT_EQ(png_colour_type(from_memory), opaque ? 2 : 6);
        EXPECT_EQ(file_bytes(from_memory), file_bytes(from_image));
    }
    const Status none = write_png((dir / "none.png").string(), 0, 10, nullptr);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().code, ErrorCode::invalid_argument);
    EXPECT_NE(none.error().message.find("none.png"), std::string::npos);
    EXPECT_FALSE(fs::exists(dir / "none.png"));
}

TEST(Png, MismatchedImageIsRejectedBeforeWriting) {
    const fs::path dir = temp_dir("mismatch");
    Image bad{10, 10, std::vector<Rgba8>(50)};
    EXPECT_EQ(write_png((dir / "m.png").string(), bad).error().code, ErrorCode::invalid_argument);
    EXPECT_FALSE(fs::exists(dir / "m.png"));
}

TEST(Png, FailedWriteLeavesTheOldFileAndNoTemporary) {
    const fs::path dir = temp_dir("atomic");
    const std::string path = (dir / "keep.png").string();
    ASSERT_TRUE(write_png(path, gradient(8, 8)).ok());
    // Replacing a directory with a file cannot succeed: the rename step fails.
    fs::create_directories(dir / "sub.png");
    EXPECT_FALSE(write_png((dir / "sub.png").string(), gradient(8, 8)).ok());
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        ++entries;
        EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
    }
    EXPECT_EQ(entries, 2u);  // keep.png and the sub.png directory
    EXPECT_TRUE(read_png(path).ok());
}

TEST(Png, WritingToADeviceWritesThroughItAndNeverReplacesIt) {
    // Renaming a temporary file over /dev/null would turn the device into a regular file.
    ASSERT_TRUE(fs::is_character_file("/dev/null"));
    EXPECT_TRUE(write_png("/dev/null", gradient(4, 4)).ok());
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    std::size_t temporaries = 0;
    for (const auto& e : fs::directory_iterator("/dev"))
        temporaries += e.path().filename().string().rfind("null.tmp", 0) == 0;
    EXPECT_EQ(temporaries, 0u);
}

TEST(Png, WritingOverADirectoryFails) {
    const fs::path dir = temp_dir("over_dir");
    const Status s = write_png(dir.string(), gradient(4, 4));
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("directory"), std::string::npos);
    EXPECT_TRUE(fs::is_directory(dir));
}

TEST(Png, ReadingGarbageOrMissingFilesIsAnErrorNamingTheFile) {
    const fs::path dir = temp_dir("garbage");
    const std::string missing = (dir / "missing.png").string();
    Result<Image> r = read_png(missing);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::io);
    EXPECT_NE(r.error().message.find(missing), std::string::npos);

    const std::string garbage = (dir / "garbage.png").string();
    std::ofstream(garbage) << "this is not a png file at all";
    r = read_png(garbage);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::bad_format);
    EXPECT_NE(r.error().message.find(garbage), std::string::npos);

    // A valid PNG cut in half.
    const std::string whole = (dir / "whole.png").string(), cut = (dir / "cut.png").string();
    ASSERT_TRUE(write_png(whole, gradient(64, 64)).ok());
    const auto size = fs::file_size(whole);
    fs::copy_file(whole, cut);
    fs::resize_file(cut, size / 2);
    EXPECT_FALSE(read_png(cut).ok());
}

TEST(Png, HugeDeclaredSizeIsRefusedBeforeAllocating) {
    // A PNG header (with a correct CRC) claiming 1,000,000 x 1,000,000 pixels: 4 TB of RGBA.
    const fs::path dir = temp_dir("huge");
    const unsigned char header[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                    0x00, 0x0f, 0x42, 0x40, 0x00, 0x0f, 0x42, 0x40, 8, 6, 0, 0, 0, 0x5c, 0x6d, 0x38, 0x7d};
    const std::string path = (dir / "huge.png").string();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(header), sizeof header);
    Result<Image> r = read_png(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::bad_format);
}

}  // namespace
