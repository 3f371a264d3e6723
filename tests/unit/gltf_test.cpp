// The glTF 2.0 reader (src/io/gltf.hpp): load_model must give exactly the Scene the assimp path
// gives, bit for bit (materials, textures, uv transforms, tangents and warnings included), for every
// glTF 2.0 file of assimp's test models and for files written here: GLB with embedded images, data
// URIs, node transforms, vertex colours; the forms it declines still load through assimp; damaged
// files get assimp's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "facet/io.hpp"
#include "facet/model.hpp"
#include "io/gltf.hpp"
#include "io/import_notes.hpp"
#include "io/resources.hpp"
#include "support/same_scene.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::expect_same_as_assimp;
using facet_test::write_file;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_gltf_test"); }

// Whether facet's glTF reader takes the file (rather than leaving it to assimp).
bool taken(const std::string& path) {
    const std::string bytes = facet_test::read_file(path);
    const LoadOptions options;
    const io_detail::ResourceRoots roots(path, options.resource_dirs);
    io_detail::ImportNotes notes;
    return io_detail::read_gltf(path, bytes, model_extension(path) == "glb", options, roots, notes).has_value();
}

void expect_taken_and_same(const std::string& path, bool expected = true) {
    EXPECT_EQ(taken(path), expected) << path;
    expect_same_as_assimp(path);
}

TEST(Gltf, AssimpTestModelsMatchAssimp) {
    FACET_REQUIRE_ASSIMP_MODELS();
    std::vector<std::string> all, declined;
    for (const auto& entry : fs::recursive_directory_iterator(facet_test::k_assimp_models / "glTF2")) {
        const std::string ext = model_extension(entry.path());
        if (entry.is_regular_file() && (ext == "gltf" || ext == "glb")) all.push_back(entry.path());
    }
    std::sort(all.begin(), all.end());
    ASSERT_GE(all.size(), 40u);
    for (const std::string& path : all) {
        expect_same_as_assimp(path);
        if (!taken(path)) declined.push_back(fs::relative(path, facet_test::k_assimp_models / "glTF2").string());
    }
    // The files meant for the reader: textured boxes (external, embedded, binary), texture transforms,
    // a camera among many nodes and meshes (2CylinderEngine), bad normals, infinite positions, and the
    // asset generator's triangle lists, strips and fans (indexed or not).
    for (const char* name : {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Embedded/BoxTextured.gltf",
                             "BoxTextured-glTF-Binary/BoxTextured.glb", "textureTransform/TextureTransformTest.gltf",
                             "2CylinderEngine-glTF-Binary/2CylinderEngine.glb", "BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
                             "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "cameras/Cameras.gltf",
                             "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf",
                             "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf",
                             "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf",
                             "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf",
                             "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf",
                             "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf"})
        EXPECT_EQ(std::count(declined.begin(), declined.end(), name), 0) << name << " was left to assimp";
    std::string list;
    for (const std::string& d : declined) list += " " + d;
    std::cout << "[ gltf ] left to assimp:" << list << "\n";
}

// Little-endian bytes of a value.
template <class T>
void put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.append(b, sizeof(T));
}

// A GLB of `json` (spaces pad it to 4 bytes) and `bin`.
std::string glb(std::string json, const std::string& bin) {
    while (json.size() % 4) json += ' ';
    std::string out = "glTF";
    put<std::uint32_t>(out, 2);
    put<std::uint32_t>(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    put<std::uint32_t>(out, static_cast<std::uint32_t>(json.size()));
    put<std::uint32_t>(out, 0x4E4F534A);
    out += json;
    put<std::uint32_t>(out, static_cast<std::uint32_t>(bin.size()));
    put<std::uint32_t>(out, 0x004E4942);
    return out + bin;
}

// Two triangles sharing an edge (a quad), with a duplicate vertex for the join, normals, uvs,
// tangents, RGBA8 colours, ushort indices: the binary chunk and its views.
struct QuadData {
    std::string bin;
    std::string views, accessors;
};

QuadData quad_data() {
    QuadData q;
    const float p[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 1, 1, 0};
    const float n[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float t[] = {0.1f, 0.9f, 0.9f, 0.9f, 0.9f, 0.1f, 0.1f, 0.1f, 0.9f, 0.1f};
    const float tan[] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, -1, 1, 0, 0, 1};
    const std::uint8_t c[] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 9, 9, 9, 255, 7, 7, 7, 7};  // the duplicate of vertex 2 differs in colour alone
    const std::uint16_t i[] = {0, 1, 2, 0, 4, 3};
    q.bin.append(reinterpret_cast<const char*>(p), sizeof p);       // 0: 60
    q.bin.append(reinterpret_cast<const char*>(n), sizeof n);       // 60: 60
    q.bin.append(reinterpret_cast<const char*>(t), sizeof t);       // 120: 40
    q.bin.append(reinterpret_cast<const char*>(tan), sizeof tan);   // 160: 80
    q.bin.append(reinterpret_cast<const char*>(c), sizeof c);       // 240: 20
    q.bin.append(reinterpret_cast<const char*>(i), sizeof i);       // 260: 12
    q.views = R"([{"buffer":0,"byteOffset":0,"byteLength":60},{"buffer":0,"byteOffset":60,"byteLength":60},
        {"buffer":0,"byteOffset":120,"byteLength":40},{"buffer":0,"byteOffset":160,"byteLength":80},
        {"buffer":0,"byteOffset":240,"byteLength":20},{"buffer":0,"byteOffset":260,"byteLength":12}])";
    q.accessors = R"([{"bufferView":0,"componentType":5126,"count":5,"type":"VEC3"},
        {"bufferView":1,"componentType":5126,"count":5,"type":"VEC3"},
        {"bufferView":2,"componentType":5126,"count":5,"type":"VEC2"},
        {"bufferView":3,"componentType":5126,"count":5,"type":"VEC4"},
        {"bufferView":4,"componentType":5121,"normalized":true,"count":5,"type":"VEC4"},
        {"bufferView":5,"componentType":5123,"count":6,"type":"SCALAR"}])";
    return q;
}

// A document around the quad: `nodes`, `materials` and `extra` (more top-level members) as given.
std::string quad_json(const QuadData& q, const std::string& buffers, const std::string& nodes, const std::string& materials,
                      const std::string& extra = "") {
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":)" + nodes +
           R"(,"meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2,"TANGENT":3,"COLOR_0":4},
           "indices":5,"material":0}]}],"materials":)" + materials + R"(,"bufferViews":)" + q.views +
           R"(,"accessors":)" + q.accessors + R"(,"buffers":)" + buffers + extra + "}";
}

std::string png_bytes(int seed) {
    Image image{4, 2, {}};
    for (int i = 0; i < 8; ++i)
        image.pixels.push_back({static_cast<std::uint8_t>(30 * i + seed), static_cast<std::uint8_t>(5 * seed), 90, 255});
    const fs::path file = temp_dir() / ("png" + std::to_string(seed) + ".png");
    EXPECT_TRUE(write_png(file.string(), image));
    return facet_test::read_file(file);
}

TEST(Gltf, GeneratedFilesMatchAssimp) {
    const QuadData q = quad_data();
    const std::string materials = R"([{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.7,0.6,0.5],"metallicFactor":0.3,
        "roughnessFactor":0.45,"baseColorTexture":{"index":0},"metallicRoughnessTexture":{"index":1}},
        "normalTexture":{"index":1,"scale":0.7},"occlusionTexture":{"index":0,"strength":0.25},
        "emissiveTexture":{"index":1,"extensions":{"KHR_texture_transform":{"offset":[0.25,0.5],"rotation":0.3,"scale":[2,3]}}},
        "emissiveFactor":[0.2,0.1,0.05],"alphaMode":"MASK","alphaCutoff":0.3,"doubleSided":true}])";
    // Images embedded in the binary chunk (after the vertex data, 4-byte aligned), two samplers.
    const std::string png0 = png_bytes(1), png1 = png_bytes(2);
    std::string bin = q.bin;
    const std::size_t at0 = bin.size();
    bin += png0;
    while (bin.size() % 4) bin += '\0';
    const std::size_t at1 = bin.size();
    bin += png1;
    while (bin.size() % 4) bin += '\0';
    const std::string views = q.views.substr(0, q.views.size() - 1) + R"(,{"buffer":0,"byteOffset":)" + std::to_string(at0) +
                              R"(,"byteLength":)" + std::to_string(png0.size()) + R"(},{"buffer":0,"byteOffset":)" +
                              std::to_string(at1) + R"(,"byteLength":)" + std::to_string(png1.size()) + "}]";
    QuadData with_images = q;
    with_images.views = views;
    const std::string images = R"(,"images":[{"bufferView":7,"mimeType":"image/png"},{"bufferView":6,"mimeType":"image/png"}],
        "samplers":[{"wrapS":33071,"wrapT":33648},{}],"textures":[{"source":0,"sampler":0},{"source":1,"sampler":1}],
        "extensionsUsed":["KHR_texture_transform"])";
    const std::string buffers = R"([{"byteLength":)" + std::to_string(bin.size()) + "}]";
    const fs::path dir = temp_dir();
    // Node transforms: a matrix, and TRS under a parent.
    const std::string trs = R"([{"children":[1,2]},{"mesh":0,"translation":[1,2,3],"rotation":[0.1,0.2,0.3,0.927],"scale":[1,2,0.5]},
        {"mesh":0,"matrix":[0,1,0,0, -1,0,0,0, 0,0,1,0, 4,5,6,1]}])";
    const std::string json = quad_json(with_images, buffers, trs, materials, images);
    expect_taken_and_same(write_file(dir / "quad.glb", glb(json, bin)));

    // The same as a .gltf with its buffer as a data URI, and as an external file.
    const std::string data_uri = "data:application/octet-stream;base64," + facet_test::base64(bin);
    expect_taken_and_same(write_file(dir / "quad_data_uri.gltf",
                                     quad_json(with_images, R"([{"byteLength":)" + std::to_string(bin.size()) + R"(,"uri":")" +
                                                                data_uri + R"("}])", trs, materials, images))
                              );
    write_file(dir / "quad.bin", bin);
    expect_taken_and_same(write_file(dir / "quad_external.gltf",
                                     quad_json(with_images, R"([{"byteLength":)" + std::to_string(bin.size()) + R"(,"uri":"quad.bin"}])",
                                               trs, materials, images))
                              );
    // Unlit, and no material at all (assimp's default one).
    const std::string plain = R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0},{"mesh":1}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]},{"primitives":[{"attributes":{"POSITION":0,"COLOR_0":1}}]}],
        "materials":[{"extensions":{"KHR_materials_unlit":{}}}],"extensionsUsed":["KHR_materials_unlit"],
        "bufferViews":[{"buffer":0,"byteLength":60},{"buffer":0,"byteOffset":60,"byteLength":60}],
        "accessors":[{"bufferView":0,"componentType":5126,"count":5,"type":"VEC3"},{"bufferView":1,"componentType":5126,"count":5,"type":"VEC3"}],
        "buffers":[{"byteLength":120}]})";
    expect_taken_and_same(write_file(dir / "plain.glb", glb(plain, q.bin.substr(0, 120))));
    // The quad's indices as a triangle strip and as a fan.
    for (const char* mode : {"5", "6"}) {
        std::string json = quad_json(q, buffers, R"([{"mesh":0}])", "[{}]");
        json.replace(json.find("\"indices\""), 0, std::string("\"mode\":") + mode + ",");
        expect_taken_and_same(write_file(dir / (std::string("mode") + mode + ".glb"), glb(json, q.bin)));
    }
}

TEST(Gltf, DeclinedFormsGoThroughAssimp) {
    const QuadData q = quad_data();
    const fs::path dir = temp_dir();
    const std::string buffers = R"([{"byteLength":)" + std::to_string(q.bin.size()) + "}]";
    const std::string material = R"([{}])";
    // Points and a second uv set: assimp's.
    std::string points = quad_json(q, buffers, R"([{"mesh":0}])", material);
    points.replace(points.find("\"indices\""), 0, "\"mode\":0,");
    expect_taken_and_same(write_file(dir / "points.glb", glb(points, q.bin)), false);
    std::string uv1 = quad_json(q, buffers, R"([{"mesh":0}])", material);
    uv1.replace(uv1.find("\"TANGENT\""), 0, "\"TEXCOORD_1\":2,");
    expect_taken_and_same(write_file(dir / "uv1.glb", glb(uv1, q.bin)), false);
    // A camera without its parameters (assimp refuses the file), and one with them (taken).
    std::string camera = quad_json(q, buffers, R"([{"mesh":0,"camera":0}])", material, R"(,"cameras":[{"type":"perspective"}])");
    expect_taken_and_same(write_file(dir / "camera_with_parameters.glb",
                                     glb(quad_json(q, buffers, R"([{"mesh":0,"camera":0}])", material,
                                                   R"(,"cameras":[{"type":"perspective","perspective":{"yfov":1,"znear":0.1}}])"),
                                         q.bin)));
    expect_taken_and_same(write_file(dir / "camera.glb", glb(camera, q.bin)), false);
}

// Forms common in Objaverse's files that assimp 5.2.5 reads and the reader takes the same way:
// KHR_materials_emissive_strength (unknown to assimp: the emissive colour stays unscaled; declined
// when the file requires it), and animations of the nodes (the scene is the nodes' own pose; a
// broken sampler is left to assimp).
TEST(Gltf, EmissiveStrengthAndAnimationsMatchAssimp) {
    const QuadData q = quad_data();
    const fs::path dir = temp_dir();
    const std::string buffers = R"([{"byteLength":)" + std::to_string(q.bin.size()) + "}]";
    const std::string emissive = R"([{"emissiveFactor":[0.5,0.25,0.1],
        "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}}])";
    expect_taken_and_same(write_file(dir / "emissive_strength.glb",
                                     glb(quad_json(q, buffers, R"([{"mesh":0}])", emissive,
                                                   R"(,"extensionsUsed":["KHR_materials_emissive_strength"])"),
                                         q.bin)));
    expect_taken_and_same(write_file(dir / "emissive_strength_required.glb",
                                     glb(quad_json(q, buffers, R"([{"mesh":0}])", emissive,
                                                   R"(,"extensionsUsed":["KHR_materials_emissive_strength"],
                                                      "extensionsRequired":["KHR_materials_emissive_strength"])"),
                                         q.bin)),
                          false);

    // Node 1 moved over two key times (the uvs' first two floats) to two positions (the quad's).
    QuadData animated = q;
    animated.accessors = q.accessors.substr(0, q.accessors.size() - 1) +
                         R"(,{"bufferView":2,"componentType":5126,"count":2,"type":"SCALAR"},
                             {"bufferView":0,"componentType":5126,"count":2,"type":"VEC3"}])";
    const std::string nodes = R"([{"children":[1]},{"mesh":0,"translation":[1,2,3],"rotation":[0.1,0.2,0.3,0.927]}])";
    auto animation = [](const std::string& input) {
        return R"(,"animations":[{"channels":[{"sampler":0,"target":{"node":1,"path":"translation"}}],
            "samplers":[{"input":)" + input + R"(,"output":7}]}])";
    };
    expect_taken_and_same(write_file(dir / "animated.glb", glb(quad_json(animated, buffers, nodes, "[{}]", animation("6")), q.bin)));
    expect_taken_and_same(write_file(dir / "animated_broken.glb", glb(quad_json(animated, buffers, nodes, "[{}]", animation("99")), q.bin)),
                          false);
}

TEST(Gltf, DamagedFilesMatchAssimp) {
    const QuadData q = quad_data();
    const fs::path dir = temp_dir();
    const std::string good = quad_json(q, R"([{"byteLength":)" + std::to_string(q.bin.size()) + "}]", R"([{"mesh":0}])", "[{}]");
    int n = 0;
    auto damaged = [&](std::string json, const std::string& bin) {
        expect_taken_and_same(write_file(dir / ("damaged" + std::to_string(n++) + ".glb"), glb(std::move(json), bin)), false);
    };
    // An index out of range, an accessor past its view, a view past its buffer, a cut binary chunk,
    // a node cycle, a buffer longer than the file: each left to assimp, whose error (or scene) stands.
    std::string bin = q.bin;
    bin[260] = 9;
    damaged(good, bin);
    std::string past = good;
    past.replace(past.find("\"count\":6"), 9, "\"count\":60");
    damaged(past, q.bin);
    std::string view = good;
    view.replace(view.find("\"byteLength\":12"), 15, "\"byteLength\":1200");
    damaged(view, q.bin);
    damaged(good, q.bin.substr(0, 100));
    std::string cycle = quad_json(q, R"([{"byteLength":272}])", R"([{"mesh":0,"children":[1]},{"children":[0]}])", "[{}]");
    damaged(cycle, q.bin);
    std::string external = quad_json(q, R"([{"byteLength":272},{"byteLength":100000,"uri":"quad.bin"}])", R"([{"mesh":0}])", "[{}]");
    external.replace(external.find("{\"buffer\":0,\"byteOffset\":0"), 11, "{\"buffer\":1");
    write_file(dir / "quad.bin", q.bin);
    damaged(external, q.bin);
}

}  // namespace
