// facet io: PNG files. Encoding is facet's own (below), decoding libspng's (opened at the first
// read); and atomic file writes.
// The encoder filters each row with Up and deflates fixed blocks of rows as independent pieces of
// one zlib stream, in parallel: the bytes depend on the image and the level alone, never on the
// number of threads.
#include <dlfcn.h>
#include <spng.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <type_traits>

#include "facet/detail/frame.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/io.hpp"

namespace facet {
namespace {

Error io_error(const std::string& path, const std::string& what) {
    return Error{ErrorCode::io, path + ": " + what};
}

// libspng's functions, from the library opened at the first PNG read (dlopen): a process that
// only writes PNGs, as `facet render` does, then loads neither libspng nor the zlib it needs at
// its start (the dynamic loader's work and the process's mappings: 0.15-0.2 ms a process,
// docs/BENCHMARKS.md).
struct Spng {
    decltype(&spng_ctx_new) ctx_new;
    decltype(&spng_ctx_free) ctx_free;
    decltype(&spng_set_image_limits) set_image_limits;
    decltype(&spng_set_png_file) set_png_file;
    decltype(&spng_get_ihdr) get_ihdr;
    decltype(&spng_decoded_image_size) decoded_image_size;
    decltype(&spng_decode_image) decode_image;
    decltype(&spng_strerror) strerror;
};

static_assert(SPNG_VERSION_MAJOR == 0, "libspng's soname below is that of its major version 0");
constexpr const char* k_spng_library = "libspng.so.0";

// The functions, or null with the reason in `why`; opened once per process, kept open.
const Spng* spng(std::string& why) {
    static std::once_flag once;
    static Spng functions{};
    static const Spng* loaded = nullptr;
    static std::string error;
    std::call_once(once, [] {
        void* library = dlopen(k_spng_library, RTLD_NOW | RTLD_LOCAL);
        if (!library) {
            const char* e = dlerror();
            error = e ? e : std::string(k_spng_library) + ": cannot be opened";
            return;
        }
        bool all = true;
        auto get = [&](auto& function, const char* name) {
            function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(library, name));
            if (!function && all) error = std::string(k_spng_library) + " has no " + name, all = false;
        };
        get(functions.ctx_new, "spng_ctx_new");
        get(functions.ctx_free, "spng_ctx_free");
        get(functions.set_image_limits, "spng_set_image_limits");
        get(functions.set_png_file, "spng_set_png_file");
        get(functions.get_ihdr, "spng_get_ihdr");
        get(functions.decoded_image_size, "spng_decoded_image_size");
        get(functions.decode_image, "spng_decode_image");
        get(functions.strerror, "spng_strerror");
        if (all) loaded = &functions;
    });
    if (!loaded) why = error;
    return loaded;
}

struct SpngDeleter {
    const Spng* functions;
    void operator()(spng_ctx* ctx) const { functions->ctx_free(ctx); }
};
using SpngContext = std::unique_ptr<spng_ctx, SpngDeleter>;

// What a PNG's header says about its rows.
struct PngLayout {
    std::uint32_t width = 0, height = 0;
    std::uint8_t bit_depth = 8, color_type = 2;  // 0 grey, 2 RGB, 6 RGBA
    std::size_t row_bytes = 0;                   // without the filter byte
};

// Each block of rows is deflated on its own (pigz's way): it starts from the 32 KB of filtered bytes
// before it as a dictionary (with runs only, the byte before it) and ends with a sync flush, so that the blocks joined are one zlib
// stream. The block's size in rows is fixed by the row's length alone (about 128 KB of filtered
// bytes: a 512x512 RGB image has 7, enough for two threads to share evenly, and the dictionary
// keeps the files within ~1% of one stream's size). Runs need no dictionary: their blocks are half
// as large, which the threads share more evenly (the bunny's PNG deflated 0.1 ms sooner, 0.6% smaller).
constexpr std::size_t k_block_bytes = 128 * 1024;
constexpr std::size_t k_run_block_bytes = 64 * 1024;
constexpr std::size_t k_window = 32 * 1024;

// Arrays written whole before they are read, so not zeroed first: the filtered rows (each thread
// writes its blocks' rows) and each block's output.
using Bytes = std::vector<unsigned char, detail::UninitialisedAllocator<unsigned char>>;

void put_u32(std::vector<unsigned char>& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(v >> shift));
}

// A chunk: length, type, data, CRC of type and data.
void put_chunk(std::vector<unsigned char>& out, const char* type, const unsigned char* data, std::size_t size) {
    put_u32(out, static_cast<std::uint32_t>(size));
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data, data + size);
    uLong crc = crc32(0, reinterpret_cast<const Bytef*>(type), 4);
    if (size > 0) crc = crc32(crc, data, static_cast<uInt>(size));  // (crc32 of a null buffer is 0, not crc)
    put_u32(out, static_cast<std::uint32_t>(crc));
}

struct DeflatedBlock {
    Bytes bytes;
    uLong adler = 1;
    std::size_t raw = 0;  // filtered bytes in
    int error = Z_OK;
};

// Deflates filtered[begin, end) as one piece of the stream: a sync flush ends it unless it is the last.
void deflate_block(const unsigned char* filtered, std::size_t begin, std::size_t end, bool last, int level,
                   bool runs_only, DeflatedBlock& out) {
    out.raw = end - begin;
    out.adler = adler32(1, filtered + begin, static_cast<uInt>(end - begin));
    z_stream z{};
    out.error = deflateInit2(&z, level, Z_DEFLATED, -15, 8, runs_only ? Z_RLE : Z_DEFAULT_STRATEGY);  // raw deflate: no header
    if (out.error != Z_OK) return;
    // Runs look one byte back only: that byte is all the dictionary they can use.
    const std::size_t dictionary = std::min(begin, runs_only ? std::size_t{1} : k_window);
    if (dictionary > 0) out.error = deflateSetDictionary(&z, filtered + begin - dictionary, static_cast<uInt>(dictionary));
    out.bytes.resize(deflateBound(&z, static_cast<uLong>(end - begin)) + 64);
    z.next_in = const_cast<Bytef*>(filtered + begin);
    z.avail_in = static_cast<uInt>(end - begin);
    std::size_t written = 0;
    const int flush = last ? Z_FINISH : Z_SYNC_FLUSH;
    while (out.error == Z_OK) {
        z.next_out = out.bytes.data() + written;
        z.avail_out = static_cast<uInt>(out.bytes.size() - written);
        const int r = deflate(&z, flush);
        written = out.bytes.size() - z.avail_out;
        if (r == Z_STREAM_END || (!last && r == Z_OK && z.avail_in == 0 && z.avail_out > 0)) break;
        if (r != Z_OK && r != Z_BUF_ERROR) out.error = r;
        else out.bytes.resize(out.bytes.size() * 2);
    }
    deflateEnd(&z);
    out.bytes.resize(written);
}

// PNG's Up filter: each byte less the one above it (the rows never overlap `out`).
void up_filter(const unsigned char* __restrict here, const unsigned char* __restrict above, unsigned char* __restrict out,
               std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>(here[i] - above[i]);
}

// Encodes the rows row(y, scratch) (row y's bytes in PNG layout, using scratch, one row long, if it
// needs to) as a PNG: signature, IHDR, one IDAT per block, IEND.
template <class Row>
Result<std::vector<unsigned char>> encode(const std::string& path, const PngLayout& layout, const PngOptions& options,
                                          const Row& row) {
    const std::size_t stride = layout.row_bytes + 1;
    const std::size_t height = layout.height;
    const std::size_t rows_per_block = std::max<std::size_t>(1, (options.runs_only ? k_run_block_bytes : k_block_bytes) / stride);
    const std::size_t blocks = (height + rows_per_block - 1) / rows_per_block;
    Bytes filtered(stride * height);
    std::vector<DeflatedBlock> deflated(blocks);
    const unsigned cores = options.threads > 0 ? static_cast<unsigned>(options.threads) : std::max(1u, std::thread::hardware_concurrency());
    detail::ThreadPool pool(static_cast<int>(std::min<std::size_t>(blocks, cores)));
    std::vector<std::vector<unsigned char>> scratch(static_cast<std::size_t>(pool.size()),
                                                    std::vector<unsigned char>(2 * layout.row_bytes));
    // Up on every row (zero above the first).
    pool.parallel_for(blocks, [&](std::size_t b, int worker) {
        unsigned char* above_scratch = scratch[static_cast<std::size_t>(worker)].data();
        unsigned char* here_scratch = above_scratch + layout.row_bytes;
        const std::size_t y0 = b * rows_per_block, y1 = std::min(height, y0 + rows_per_block);
        const unsigned char* above = y0 > 0 ? row(static_cast<std::uint32_t>(y0 - 1), above_scratch) : nullptr;
        for (std::size_t y = y0; y < y1; ++y) {
            const unsigned char* here = row(static_cast<std::uint32_t>(y), here_scratch);
            unsigned char* out = filtered.data() + y * stride;
            out[0] = 2;
            if (above)
                up_filter(here, above, out + 1, layout.row_bytes);
            else
                std::memcpy(out + 1, here, layout.row_bytes);
            above = here;
            std::swap(above_scratch, here_scratch);  // `here` may live in here_scratch: keep it
        }
    });
    pool.parallel_for(blocks, [&](std::size_t b) {
        const std::size_t begin = b * rows_per_block * stride, end = std::min(height, (b + 1) * rows_per_block) * stride;
        deflate_block(filtered.data(), begin, end, b + 1 == blocks, options.level, options.runs_only, deflated[b]);
    });

    std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::array<unsigned char, 13> ihdr{};
    for (int i = 0; i < 4; ++i) {
        ihdr[static_cast<std::size_t>(i)] = static_cast<unsigned char>(layout.width >> (24 - 8 * i));
        ihdr[static_cast<std::size_t>(4 + i)] = static_cast<unsigned char>(layout.height >> (24 - 8 * i));
    }
    ihdr[8] = layout.bit_depth;
    ihdr[9] = layout.color_type;  // compression, filter method and interlace stay 0
    put_chunk(png, "IHDR", ihdr.data(), ihdr.size());
    // The zlib header (deflate, 32 KB window, the level's class as zlib writes it) leads the first
    // block's IDAT; the Adler-32 of all the filtered bytes, combined from the blocks', ends the last's.
    const int level_class = options.level < 2 || options.runs_only ? 0 : options.level < 6 ? 1 : options.level == 6 ? 2 : 3;
    unsigned header[2] = {0x78, static_cast<unsigned>(level_class << 6)};
    header[1] += 31 - (header[0] * 256 + header[1]) % 31;
    uLong adler = 1;
    for (std::size_t b = 0; b < blocks; ++b) {
        DeflatedBlock& d = deflated[b];
        if (d.error != Z_OK)
            return io_error(path, d.error == Z_MEM_ERROR ? "out of memory encoding the PNG" : "PNG encoding failed (zlib " + std::to_string(d.error) + ")");
        adler = adler32_combine(adler, d.adler, static_cast<z_off_t>(d.raw));
        if (b == 0) d.bytes.insert(d.bytes.begin(), {static_cast<unsigned char>(header[0]), static_cast<unsigned char>(header[1])});
        if (b + 1 == blocks)
            for (int shift = 24; shift >= 0; shift -= 8) d.bytes.push_back(static_cast<unsigned char>(adler >> shift));
        put_chunk(png, "IDAT", d.bytes.data(), d.bytes.size());
    }
    put_chunk(png, "IEND", nullptr, 0);
    return png;
}

// Whether every one of the n pixels has alpha 255 (an AND over all of them, which the compiler
// vectorizes).
bool opaque(const Rgba8* pixels, std::size_t n) {
    std::uint32_t all = ~0u;
    for (std::size_t i = 0; i < n; ++i) all &= static_cast<std::uint32_t>(pixels[i].a);
    return all == 255;
}

// An 8-bit image: RGB when it is opaque (the same pixels read back, a quarter less to compress),
// RGBA otherwise.
Result<std::vector<unsigned char>> encode_image(const std::string& path, int w, int h, const Rgba8* image,
                                                const PngOptions& options) {
    const auto width = static_cast<std::size_t>(w);
    const auto* pixels = reinterpret_cast<const unsigned char*>(image);
    PngLayout layout{static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), 8, 6, width * 4};
    if (!opaque(image, width * static_cast<std::size_t>(h)))
        return encode(path, layout, options, [&](std::uint32_t y, unsigned char*) { return pixels + y * width * 4; });
    layout.color_type = 2;
    layout.row_bytes = width * 3;
    return encode(path, layout, options, [&](std::uint32_t y, unsigned char* rgb) {
        const unsigned char* from = pixels + y * width * 4;
        for (std::size_t x = 0; x < width; ++x) {
            rgb[3 * x] = from[4 * x];
            rgb[3 * x + 1] = from[4 * x + 1];
            rgb[3 * x + 2] = from[4 * x + 2];
        }
        return rgb;
    });
}

}  // namespace

namespace {

// Writes straight to `path`: for targets that are not regular files (/dev/null, /dev/stdout, a
// fifo), where renaming a temporary over them would replace the device itself.
Status write_file_direct(const std::string& path, const void* bytes, std::size_t size) {
    std::ofstream out(path, std::ios::binary);
    if (!out) return io_error(path, std::string("cannot open for writing: ") + std::strerror(errno));
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    out.flush();
    if (!out) return io_error(path, "write failed");
    return Ok{};
}

}  // namespace

Status write_file_atomic(const std::string& path, const void* bytes, std::size_t size) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    std::error_code status_error;
    const fs::file_status status = fs::status(target, status_error);
    if (fs::exists(status) && !fs::is_regular_file(status)) {
        if (fs::is_directory(status)) return io_error(path, "is a directory");
        return write_file_direct(path, bytes, size);
    }
    // Same directory as the target, so the rename cannot cross file systems.
    std::random_device rd;
    const fs::path temp = target.parent_path() /
                          (target.filename().string() + ".tmp" + std::to_string(rd() % 1000000));
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) return io_error(path, std::string("cannot create the file: ") + std::strerror(errno));
        out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
        // close() reports what the last write or the file system's flush refused (ENOSPC, EDQUOT,
        // EIO on network file systems); only a file that closed cleanly is renamed into place.
        out.close();
        if (!out) {
            std::error_code ignored;
            fs::remove(temp, ignored);
            return io_error(path, "write failed (disk full?)");
        }
    }
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(temp, ignored);
        return io_error(path, "cannot move the finished file into place: " + ec.message());
    }
    return Ok{};
}

Status write_png(const std::string& path, const Image& image, const PngOptions& options) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
        return Error{ErrorCode::invalid_argument, path + ": image size and pixel count do not match"};
    return write_png(path, image.width, image.height, image.pixels.data(), options);
}

Status write_png(const std::string& path, int width, int height, const Rgba8* pixels, const PngOptions& options) {
    if (width <= 0 || height <= 0 || !pixels)
        return Error{ErrorCode::invalid_argument, path + ": the image has no pixels"};
    if (options.level < 0 || options.level > 9)
        return Error{ErrorCode::invalid_argument, path + ": PNG level " + std::to_string(options.level) + " is not in 0..9"};
    auto png = encode_image(path, width, height, pixels, options);
    if (!png) return png.error();
    return write_file_atomic(path, png->data(), png->size());
}

namespace {

// A PNG of `channels` samples per pixel (8 or 16 bits as T), `color_type`'s, from width * height *
// channels values, first row at the top.
template <class T>
Status write_png_samples(const std::string& path, int width, int height, const std::vector<T>& values, int channels,
                         std::uint8_t color_type) {
    if (width <= 0 || height <= 0 || values.size() != static_cast<std::size_t>(width) * height * channels)
        return Error{ErrorCode::invalid_argument, path + ": image size and value count do not match"};
    const auto row_values = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
    const PngLayout layout{static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), 8 * sizeof(T), color_type,
                           row_values * sizeof(T)};
    auto png = encode(path, layout, PngOptions{}, [&](std::uint32_t y, unsigned char* scratch) {
        const T* from = values.data() + y * row_values;
        if constexpr (sizeof(T) == 1) {
            return reinterpret_cast<const unsigned char*>(from);
        } else {
            for (std::size_t i = 0; i < row_values; ++i) {  // PNG's samples are big-endian
                scratch[2 * i] = static_cast<unsigned char>(from[i] >> 8);
                scratch[2 * i + 1] = static_cast<unsigned char>(from[i]);
            }
            return static_cast<const unsigned char*>(scratch);
        }
    });
    if (!png) return png.error();
    return write_file_atomic(path, png->data(), png->size());
}

}  // namespace

Status write_png_gray8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& values) {
    return write_png_samples(path, width, height, values, 1, 0);
}

Status write_png_gray16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& values) {
    return write_png_samples(path, width, height, values, 1, 0);
}

Status write_png_rgb16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& values) {
    return write_png_samples(path, width, height, values, 3, 2);
}

Result<Image> read_png(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!file) return io_error(path, std::string("cannot open: ") + std::strerror(errno));
    std::string why;
    const Spng* const f = spng(why);
    if (!f) return io_error(path, "cannot decode PNG files: " + why);
    SpngContext ctx(f->ctx_new(0), SpngDeleter{f});
    if (!ctx) return io_error(path, "out of memory creating the PNG decoder");
    // Refuse absurd sizes before allocating: a hostile header can claim 2^31 x 2^31 pixels.
    f->set_image_limits(ctx.get(), k_max_target_size * 2, k_max_target_size * 2);
    f->set_png_file(ctx.get(), file.get());
    spng_ihdr ihdr{};
    int err = f->get_ihdr(ctx.get(), &ihdr);
    std::size_t size = 0;
    if (!err) err = f->decoded_image_size(ctx.get(), SPNG_FMT_RGBA8, &size);
    if (err) return Error{ErrorCode::bad_format, path + ": not a valid PNG file (" + f->strerror(err) + ")"};
    Image image;
    image.width = static_cast<int>(ihdr.width);
    image.height = static_cast<int>(ihdr.height);
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
    err = f->decode_image(ctx.get(), image.pixels.data(), size, SPNG_FMT_RGBA8, SPNG_DECODE_TRNS);
    if (err) return Error{ErrorCode::bad_format, path + ": corrupt PNG data (" + f->strerror(err) + ")"};
    return image;
}

}  // namespace facet
