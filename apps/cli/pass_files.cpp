// facet command line: one view's render passes into files (pass_files.hpp): PNG, NumPy .npy and
// OpenEXR (through libfacet_exr.so, exr_module.hpp).
#include "pass_files.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "exr_module.hpp"
#include "facet/detail/module.hpp"
#include "facet/io.hpp"

namespace facet::cli {
namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t k_largest_png16 = 65535;

// transforms.json's key for a pass's file.
std::string key_of(Pass p) {
    if (p == Pass::colour) return "file_path";
    if (p == Pass::alpha) return "mask_path";
    return std::string(pass_name(p)) + "_file_path";
}

int id_index(Pass p) { return p == Pass::instance ? 0 : p == Pass::material ? 1 : 2; }
bool is_id(Pass p) { return p == Pass::instance || p == Pass::material || p == Pass::primitive; }

std::uint16_t scaled16(float v, float scale) {
    const float s = v / scale;
    return std::isfinite(s) && s >= 0 && s < 65535.5f ? static_cast<std::uint16_t>(std::lround(s)) : 0;
}
std::uint16_t unit16(float v) {
    const float c = v > 0 ? (v < 1 ? v : 1) : 0;  // NaN to 0
    return static_cast<std::uint16_t>(std::lround(c * 65535.0f));
}

// The EXR file of a view: every pass but colour, as channels.
Status write_exr(const std::string& path, const ViewImages& v, PassSet passes) {
    std::string why;
    const auto write = reinterpret_cast<WriteExr>(detail::module_symbol(k_exr_module, k_exr_write_symbol, why));
    if (!write) return Error{ErrorCode::io, path + ": cannot write OpenEXR files: " + why};
    std::vector<ExrChannel> channels;
    auto add = [&](const char* name, bool is_uint, const void* first, int components) {
        channels.push_back({name, is_uint, first, static_cast<std::size_t>(components) * 4});
    };
    if (passes.has(Pass::alpha)) add("A", false, v.alpha.data(), 1);
    if (passes.has(Pass::depth)) add("Z", false, v.depth.data(), 1);
    if (passes.has(Pass::range)) add("range", false, v.range.data(), 1);
    if (passes.has(Pass::normal)) {
        add("N.X", false, &v.normal[0].x, 3);
        add("N.Y", false, &v.normal[0].y, 3);
        add("N.Z", false, &v.normal[0].z, 3);
    }
    if (passes.has(Pass::uv)) {
        add("uv.U", false, &v.uv[0].x, 2);
        add("uv.V", false, &v.uv[0].y, 2);
    }
    if (passes.has(Pass::instance)) add("instance", true, v.instance.data(), 1);
    if (passes.has(Pass::material)) add("material", true, v.material.data(), 1);
    if (passes.has(Pass::primitive)) add("primitive", true, v.primitive.data(), 1);
    // Atomically, as write_file_atomic does: a temporary beside it, renamed when complete.
    static std::atomic<unsigned> counter{0};
    const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + std::to_string(counter++);
    std::array<char, 512> error{};
    if (write(tmp.c_str(), v.width, v.height, channels.data(), static_cast<int>(channels.size()), error.data(), error.size()) != 0) {
        std::error_code ec;
        fs::remove(tmp, ec);
        return Error{ErrorCode::io, path + ": cannot write the OpenEXR file: " + error.data()};
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        return Error{ErrorCode::io, path + ": cannot write: " + ec.message()};
    }
    return Ok{};
}

// One pass of one view into its own file: `file` is its path relative to the folder without the
// extension, which is added.
Status write_pass(const ViewImages& v, Pass p, const PassFileOptions& o, std::string& file) {
    const int w = v.width, h = v.height;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    auto to = [&](const char* ext) {
        file = file + ext;
        return (fs::path(o.folder) / file).string();
    };
    // By runs, as facet render's PNG: the colour pass of a view is that render's file, byte for byte.
    if (p == Pass::colour) return write_png(to(".png"), Image{w, h, {v.colour.begin(), v.colour.end()}}, {.runs_only = true});
    if (p == Pass::alpha) {
        std::vector<std::uint8_t> bytes(n);
        for (std::size_t i = 0; i < n; ++i) bytes[i] = static_cast<std::uint8_t>(std::lround(v.alpha[i] * 255.0f));
        return write_png_gray8(to(".png"), w, h, bytes);
    }
    if (is_id(p)) {
        const std::uint32_t* ids = p == Pass::instance ? v.instance.data() : p == Pass::material ? v.material.data() : v.primitive.data();
        if (o.largest_id[id_index(p)] > k_largest_png16) return write_npy(to(".npy"), ids, "<u4", {h, w});
        return write_png_gray16(to(".png"), w, h, std::vector<std::uint16_t>(ids, ids + n));
    }
    if (o.format == FloatFormat::npy) {
        if (p == Pass::depth) return write_npy(to(".npy"), v.depth.data(), "<f4", {h, w});
        if (p == Pass::range) return write_npy(to(".npy"), v.range.data(), "<f4", {h, w});
        if (p == Pass::normal) return write_npy(to(".npy"), v.normal.data(), "<f4", {h, w, 3});
        return write_npy(to(".npy"), v.uv.data(), "<f4", {h, w, 2});
    }
    // PNG.
    if (p == Pass::depth || p == Pass::range) {
        const float* values = p == Pass::depth ? v.depth.data() : v.range.data();
        std::vector<std::uint16_t> steps(n);
        for (std::size_t i = 0; i < n; ++i) steps[i] = scaled16(values[i], o.depth_scale);
        return write_png_gray16(to(".png"), w, h, steps);
    }
    if (p == Pass::normal) {
        Image img{w, h, std::vector<Rgba8>(n)};
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 c = v.normal[i];
            img.pixels[i] = c == Vec3{} ? Rgba8{0, 0, 0, 255} : to_rgba8({0.5f + 0.5f * c.x, 0.5f + 0.5f * c.y, 0.5f + 0.5f * c.z, 1});
        }
        return write_png(to(".png"), img);
    }
    std::vector<std::uint16_t> rgb(3 * n);
    for (std::size_t i = 0; i < n; ++i) rgb[3 * i] = unit16(v.uv[i].x), rgb[3 * i + 1] = unit16(v.uv[i].y);
    return write_png_rgb16(to(".png"), w, h, rgb);
}

}  // namespace

std::vector<std::string> pass_folders(PassSet passes, FloatFormat format) {
    std::vector<std::string> folders;
    bool exr = false;
    for (Pass p : k_all_passes) {
        if (!passes.has(p)) continue;
        if (format == FloatFormat::exr && p != Pass::colour) exr = true;
        else folders.push_back(pass_name(p));
    }
    if (exr) folders.push_back("exr");
    return folders;
}

Result<PassFiles> write_pass_files(const ViewImages& v, PassSet passes, const std::string& name, const PassFileOptions& o) {
    PassFiles out;
    std::string exr_file;
    for (Pass p : k_all_passes) {
        if (!passes.has(p)) continue;
        if (o.format == FloatFormat::exr && p != Pass::colour) {
            if (exr_file.empty()) {
                exr_file = "exr/" + name + ".exr";
                if (Status s = write_exr((fs::path(o.folder) / exr_file).string(), v, passes); !s) return s.error();
                out.files.push_back(exr_file);
            }
            out.keys.emplace_back(key_of(p), exr_file);
            continue;
        }
        std::string file = std::string(pass_name(p)) + "/" + name;
        if (Status s = write_pass(v, p, o, file); !s) return s.error();
        out.keys.emplace_back(key_of(p), file);
        out.files.push_back(file);
    }
    return out;
}

void load_writers_for(const RenderPlan& plan) {
    std::string why;
    if (plan.views && plan.views->float_format == FloatFormat::exr) (void)detail::module_symbol(k_exr_module, k_exr_write_symbol, why);
}

Status write_npy(const std::string& path, const void* data, std::string_view dtype, const std::vector<int>& shape) {
    std::string dims;
    std::size_t count = 1;
    for (int d : shape) {
        dims += std::to_string(d) + ", ";
        count *= static_cast<std::size_t>(d);
    }
    if (shape.size() > 1) dims.resize(dims.size() - 2);  // (H, W); a 1-tuple keeps its comma
    std::string header = "{'descr': '" + std::string(dtype) + "', 'fortran_order': False, 'shape': (" + dims + "), }";
    // The header, padded with spaces and ended by a newline, makes the data start at a multiple of 64.
    const std::size_t preamble = 10;
    header.append(63 - (preamble + header.size()) % 64, ' ');
    header += '\n';
    std::string bytes = "\x93NUMPY";
    bytes += '\x01';
    bytes += '\x00';
    const auto length = static_cast<std::uint16_t>(header.size());
    bytes += static_cast<char>(length & 0xff);
    bytes += static_cast<char>(length >> 8);
    bytes += header;
    const std::size_t element = 4;
    bytes.append(static_cast<const char*>(data), count * element);
    return write_file_atomic(path, bytes.data(), bytes.size());
}

}  // namespace facet::cli
