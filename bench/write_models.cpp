// facet benchmarks: writes the model files the loading benchmark reads (scripts/bench-loading), so
// that nothing that large is committed. Not a stage of the renderer.
//   sphere_1m.obj   the geodesic sphere of 1,003,520 triangles (bench_scenes.hpp) as positions and
//                   faces, numbers as "%.6f" (as Blender writes them): about 39 MB
//   textured.glb    four spheres side by side, each with a 2048x2048 JPEG base-colour texture of its
//                   own, embedded (as Objaverse's GLB files are)
//   textured_png.glb the same with PNG textures
//   texture_2048.jpg the first of the JPEG textures alone
//   sphere_1m.glb   the geodesic sphere of sphere_1m.obj as GLB (positions, normals, 32-bit indices)
// Usage: facet_bench_write_models OUT_DIR
#include <turbojpeg.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "facet/image.hpp"
#include "facet/io.hpp"
#include "facet/mesh.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;

bool write_obj(const fs::path& path, const Mesh& mesh) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "wb"), std::fclose);
    if (!f) return false;
    std::fprintf(f.get(), "# geodesic sphere, %zu triangles\n", mesh.triangle_count());
    for (const Vec3& p : mesh.positions) std::fprintf(f.get(), "v %.6f %.6f %.6f\n", p.x, p.y, p.z);
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
        std::fprintf(f.get(), "f %u %u %u\n", mesh.indices[t] + 1, mesh.indices[t + 1] + 1, mesh.indices[t + 2] + 1);
    return std::ferror(f.get()) == 0;
}

// A texture with detail at every scale (so that neither JPEG nor PNG compresses it to nothing):
// rings, a colour gradient per sphere and hashed noise.
Image texture_pattern(int size, int which) {
    Image image{size, size, std::vector<Rgba8>(static_cast<std::size_t>(size) * size)};
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u ^
                              static_cast<std::uint32_t>(which) * 83492791u;
            h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
            const float u = static_cast<float>(x) / size, v = static_cast<float>(y) / size;
            const float ring = 0.5f + 0.5f * std::sin(40.0f * std::hypot(u - 0.5f, v - 0.5f) + which);
            auto channel = [&](float base) {
                const float c = 255.0f * (0.6f * base + 0.3f * ring) + static_cast<float>(h & 31);
                return static_cast<std::uint8_t>(std::min(255.0f, c));
            };
            image.pixels[static_cast<std::size_t>(y) * size + x] = {channel(u), channel(v), channel(0.25f * which), 255};
        }
    return image;
}

std::string jpeg_bytes(const Image& image) {
    tjhandle tj = tjInitCompress();
    unsigned char* out = nullptr;
    unsigned long size = 0;
    const int ok = tjCompress2(tj, reinterpret_cast<const unsigned char*>(image.pixels.data()), image.width, 0, image.height,
                               TJPF_RGBA, &out, &size, TJSAMP_420, 90, 0);
    std::string bytes = ok == 0 ? std::string(reinterpret_cast<char*>(out), size) : std::string();
    tjFree(out);
    tjDestroy(tj);
    return bytes;
}

std::string png_bytes(const Image& image, const fs::path& scratch) {
    if (!write_png(scratch.string(), image)) return {};
    std::ifstream in(scratch, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fs::remove(scratch);
    return bytes;
}

void pad4(std::string& s, char with) {
    while (s.size() % 4) s += with;
}

// `textures` copies of `sphere` (positions, normals and uvs when it has them, 32-bit indices) in one
// buffer, each with its own material and embedded image; with no textures, one copy and no material.
bool write_glb(const fs::path& path, const Mesh& sphere, int textures, bool jpeg) {
    const int k_count = std::max(textures, 1), k_size = 2048;
    std::string bin, json_meshes, json_nodes, json_accessors, json_views, json_materials, json_textures, json_images;
    int view = 0, accessor = 0;
    auto add_view = [&](const void* data, std::size_t bytes) {
        pad4(bin, '\0');
        if (view) json_views += ",";
        json_views += "{\"buffer\":0,\"byteOffset\":" + std::to_string(bin.size()) + ",\"byteLength\":" + std::to_string(bytes) + "}";
        bin.append(static_cast<const char*>(data), bytes);
        return view++;
    };
    auto add_accessor = [&](int v, int component, std::size_t count, const char* type, const std::string& extra) {
        if (accessor) json_accessors += ",";
        json_accessors += "{\"bufferView\":" + std::to_string(v) + ",\"componentType\":" + std::to_string(component) +
                          ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"" + extra + "}";
        return accessor++;
    };
    Aabb box = sphere.bounds();
    const std::string minmax = "," + std::string("\"min\":[") + std::to_string(box.min.x) + "," + std::to_string(box.min.y) +
                               "," + std::to_string(box.min.z) + "],\"max\":[" + std::to_string(box.max.x) + "," +
                               std::to_string(box.max.y) + "," + std::to_string(box.max.z) + "]";
    const std::size_t n = sphere.positions.size();
    const int pos = add_accessor(add_view(sphere.positions.data(), n * sizeof(Vec3)), 5126, n, "VEC3", minmax);
    const int nor = sphere.normals.empty() ? -1 : add_accessor(add_view(sphere.normals.data(), n * sizeof(Vec3)), 5126, n, "VEC3", "");
    const int uv = sphere.uvs.empty() ? -1 : add_accessor(add_view(sphere.uvs.data(), n * sizeof(Vec2)), 5126, n, "VEC2", "");
    const int idx = add_accessor(add_view(sphere.indices.data(), sphere.indices.size() * 4), 5125, sphere.indices.size(), "SCALAR", "");
    std::string scene_nodes;
    for (int i = 0; i < k_count; ++i) {
        const std::string s = std::to_string(i), sep = i ? "," : "";
        std::string attributes = "\"POSITION\":" + std::to_string(pos);
        if (nor >= 0) attributes += ",\"NORMAL\":" + std::to_string(nor);
        if (uv >= 0) attributes += ",\"TEXCOORD_0\":" + std::to_string(uv);
        json_meshes += sep + "{\"primitives\":[{\"attributes\":{" + attributes + "},\"indices\":" + std::to_string(idx) +
                       (textures ? ",\"material\":" + s : std::string()) + "}]}";
        json_nodes += sep + "{\"mesh\":" + s + ",\"translation\":[" + std::to_string(2.5 * i) + ",0,0]}";
        scene_nodes += sep + s;
        if (!textures) continue;
        const Image image = texture_pattern(k_size, i);
        const std::string bytes = jpeg ? jpeg_bytes(image) : png_bytes(image, path.string() + ".tmp.png");
        if (bytes.empty()) return false;
        if (jpeg && i == 0) {  // the first texture alone too, for facet_bench_jpeg
            std::ofstream alone(path.parent_path() / "texture_2048.jpg", std::ios::binary);
            alone << bytes;
        }
        const int image_view = add_view(bytes.data(), bytes.size());
        json_images += sep + "{\"bufferView\":" + std::to_string(image_view) + ",\"mimeType\":\"image/" + (jpeg ? "jpeg" : "png") + "\"}";
        json_textures += sep + "{\"source\":" + s + "}";
        json_materials += sep + "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":" + s + "}}}";
    }
    pad4(bin, '\0');
    std::string json = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"facet_bench_write_models\"},\"scene\":0,\"scenes\":[{\"nodes\":[" +
                       scene_nodes + "]}],\"nodes\":[" + json_nodes + "],\"meshes\":[" + json_meshes +
                       (textures ? "],\"materials\":[" + json_materials + "],\"textures\":[" + json_textures + "],\"images\":[" +
                                       json_images
                                 : std::string()) +
                       "],\"accessors\":[" + json_accessors + "],\"bufferViews\":[" + json_views +
                       "],\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + "}]}";
    pad4(json, ' ');
    auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const std::uint32_t total = static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size());
    std::ofstream out(path, std::ios::binary);
    out << "glTF" << u32(2) << u32(total) << u32(static_cast<std::uint32_t>(json.size())) << "JSON" << json
        << u32(static_cast<std::uint32_t>(bin.size())) << std::string("BIN\0", 4) << bin;
    return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 || std::string(argv[1]) == "--help") {
        std::cout << "usage: facet_bench_write_models OUT_DIR\n"
                     "Writes sphere_1m.obj (1,003,520 triangles, ~39 MB), textured.glb (four 2048x2048 JPEG textures)\n"
                     "textured_png.glb (the same with PNG)\n"
                     "and sphere_1m.glb (the sphere as GLB) into OUT_DIR, for scripts/bench-loading.\n";
        return argc == 2 ? 0 : 2;
    }
    const fs::path out = argv[1];
    std::error_code ec;
    fs::create_directories(out, ec);
    const Mesh sphere = bench::make_geodesic_sphere(1.0f, bench::k_million_sphere_frequency);
    const Mesh uv_sphere = make_uv_sphere(1.0f, 96, 48);
    if (!write_obj(out / "sphere_1m.obj", sphere) || !write_glb(out / "textured.glb", uv_sphere, 4, true) ||
        !write_glb(out / "textured_png.glb", uv_sphere, 4, false) || !write_glb(out / "sphere_1m.glb", sphere, 0, false)) {
        std::cerr << "facet_bench_write_models: cannot write into " << out << "\n";
        return 1;
    }
    return 0;
}
