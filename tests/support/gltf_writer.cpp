// Test support: glTF 2.0 documents from facet meshes (gltf_writer.hpp).
#include "support/gltf_writer.hpp"

#include <cstdint>
#include <cstring>
#include <sstream>

#include "facet/io.hpp"
#include "support/test_data.hpp"

namespace facet_test {
namespace {

template <class T>
void append(std::string& buffer, const std::vector<T>& v) {
    const std::size_t at = buffer.size();
    buffer.resize(at + v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(buffer.data() + at, v.data(), v.size() * sizeof(T));
}

void texture_info(std::ostringstream& j, const char* key, const GltfTextureRef& t, int texture_index,
                  const std::string& extra = "") {
    if (t.image < 0) return;
    j << ",\"" << key << "\":{\"index\":" << texture_index << extra;
    if (!t.extensions.empty()) j << ",\"extensions\":" << t.extensions;
    j << "}";
}

}  // namespace

std::string write_gltf(const std::filesystem::path& path, const GltfDocument& doc) {
    std::string buffer;
    struct View {
        std::size_t offset, length;
    };
    std::vector<View> views;
    std::ostringstream accessors, meshes, nodes;
    int accessor = 0;
    auto add_view = [&](auto const& v) {
        views.push_back({buffer.size(), v.size() * sizeof(v[0])});
        append(buffer, v);
        return static_cast<int>(views.size()) - 1;
    };
    for (std::size_t n = 0; n < doc.nodes.size(); ++n) {
        const GltfNode& node = doc.nodes[n];
        const facet::Mesh& m = node.mesh;
        facet::Aabb box = m.bounds();
        std::ostringstream attributes;
        auto accessor_of = [&](int view, std::size_t count, const char* type, bool bounds) {
            accessors << (accessor ? "," : "") << "{\"bufferView\":" << view << ",\"componentType\":5126,\"count\":"
                      << count << ",\"type\":\"" << type << "\"";
            if (bounds)
                accessors << ",\"min\":[" << box.min.x << "," << box.min.y << "," << box.min.z << "],\"max\":[" << box.max.x
                          << "," << box.max.y << "," << box.max.z << "]";
            accessors << "}";
            return accessor++;
        };
        attributes << "\"POSITION\":" << accessor_of(add_view(m.positions), m.positions.size(), "VEC3", true);
        if (!m.normals.empty()) attributes << ",\"NORMAL\":" << accessor_of(add_view(m.normals), m.normals.size(), "VEC3", false);
        if (!m.uvs.empty()) attributes << ",\"TEXCOORD_0\":" << accessor_of(add_view(m.uvs), m.uvs.size(), "VEC2", false);
        if (!m.tangents.empty())
            attributes << ",\"TANGENT\":" << accessor_of(add_view(m.tangents), m.tangents.size(), "VEC4", false);
        const int view = add_view(m.indices);
        accessors << ",{\"bufferView\":" << view << ",\"componentType\":5125,\"count\":" << m.indices.size()
                  << ",\"type\":\"SCALAR\"}";
        const int indices = accessor++;
        meshes << (n ? "," : "") << "{\"primitives\":[{\"attributes\":{" << attributes.str() << "},\"indices\":" << indices
               << ",\"material\":" << node.material << "}]}";
        nodes << (n ? "," : "") << "{\"mesh\":" << n << ",\"translation\":[" << node.translation.x << ","
              << node.translation.y << "," << node.translation.z << "]}";
    }
    std::ostringstream j;
    j.precision(9);
    j << "{\"asset\":{\"version\":\"2.0\"}";
    if (!doc.extensions_used.empty()) {
        j << ",\"extensionsUsed\":[";
        for (std::size_t i = 0; i < doc.extensions_used.size(); ++i) j << (i ? "," : "") << '"' << doc.extensions_used[i] << '"';
        j << "]";
    }
    j << ",\"scene\":0,\"scenes\":[{\"nodes\":[";
    for (std::size_t n = 0; n < doc.nodes.size(); ++n) j << (n ? "," : "") << n;
    j << "]}],\"nodes\":[" << nodes.str() << "],\"meshes\":[" << meshes.str() << "],\"materials\":[";
    // One texture (with its own sampler) per texture reference, in order.
    std::ostringstream textures, samplers;
    int texture_count = 0;
    auto texture_of = [&](const GltfTextureRef& t) {
        if (t.image < 0) return -1;
        textures << (texture_count ? "," : "") << "{\"source\":" << t.image << ",\"sampler\":" << texture_count << "}";
        samplers << (texture_count ? "," : "") << "{\"wrapS\":" << t.wrap_s << ",\"wrapT\":" << t.wrap_t << "}";
        return texture_count++;
    };
    for (std::size_t i = 0; i < doc.materials.size(); ++i) {
        const GltfMaterial& m = doc.materials[i];
        j << (i ? "," : "") << "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[" << m.base_colour[0] << ","
          << m.base_colour[1] << "," << m.base_colour[2] << "," << m.base_colour[3] << "],\"metallicFactor\":" << m.metallic
          << ",\"roughnessFactor\":" << m.roughness;
        texture_info(j, "baseColorTexture", m.base_colour_texture, texture_of(m.base_colour_texture));
        texture_info(j, "metallicRoughnessTexture", m.metallic_roughness_texture, texture_of(m.metallic_roughness_texture));
        j << "}";
        std::ostringstream scale, strength;
        scale << ",\"scale\":" << m.normal_scale;
        strength << ",\"strength\":" << m.occlusion_strength;
        texture_info(j, "normalTexture", m.normal_texture, texture_of(m.normal_texture), scale.str());
        texture_info(j, "occlusionTexture", m.occlusion_texture, texture_of(m.occlusion_texture), strength.str());
        texture_info(j, "emissiveTexture", m.emissive_texture, texture_of(m.emissive_texture));
        j << ",\"emissiveFactor\":[" << m.emissive[0] << "," << m.emissive[1] << "," << m.emissive[2] << "]";
        j << ",\"alphaMode\":\"" << m.alpha_mode << "\",\"alphaCutoff\":" << m.alpha_cutoff
          << ",\"doubleSided\":" << (m.double_sided ? "true" : "false");
        if (!m.extensions.empty()) j << ",\"extensions\":" << m.extensions;
        j << "}";
    }
    j << "]";
    if (texture_count) j << ",\"textures\":[" << textures.str() << "],\"samplers\":[" << samplers.str() << "]";
    if (!doc.images.empty()) {
        j << ",\"images\":[";
        for (std::size_t i = 0; i < doc.images.size(); ++i) {
            const std::string name = path.stem().string() + "_image" + std::to_string(i) + ".png";
            const facet::Status written = facet::write_png((path.parent_path() / name).string(), doc.images[i]);
            if (!written) return written.error().message;  // the loader will then fail, naming it
            j << (i ? "," : "") << "{\"uri\":\"" << name << "\"}";
        }
        j << "]";
    }
    j << ",\"buffers\":[{\"byteLength\":" << buffer.size() << ",\"uri\":\"data:application/octet-stream;base64,"
      << base64(buffer) << "\"}],\"bufferViews\":[";
    for (std::size_t v = 0; v < views.size(); ++v)
        j << (v ? "," : "") << "{\"buffer\":0,\"byteOffset\":" << views[v].offset << ",\"byteLength\":" << views[v].length << "}";
    j << "],\"accessors\":[" << accessors.str() << "]}";
    return write_file(path, j.str());
}

facet::Mesh facing_quad(bool mirrored_u) {
    facet::Mesh m;
    m.positions = {{-1, 1, 0}, {1, 1, 0}, {1, -1, 0}, {-1, -1, 0}};
    m.normals.assign(4, facet::Vec3{0, 0, 1});
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    if (mirrored_u)
        for (facet::Vec2& uv : m.uvs) uv.x = 1 - uv.x;
    m.indices = {0, 3, 2, 0, 2, 1};
    return m;
}

GltfDocument sphere_grid(int rows, int columns, float spacing, const float (&colour)[3]) {
    GltfDocument doc;
    const facet::Mesh sphere = facet::make_uv_sphere(1.0f, 64, 32);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c) {
            GltfMaterial m;
            for (int k = 0; k < 3; ++k) m.base_colour[k] = colour[k];
            m.metallic = rows > 1 ? static_cast<float>(r) / static_cast<float>(rows - 1) : 0.0f;
            m.roughness = columns > 1 ? static_cast<float>(c) / static_cast<float>(columns - 1) : 0.5f;
            doc.materials.push_back(m);
            GltfNode node{sphere, static_cast<int>(doc.materials.size()) - 1,
                          {(static_cast<float>(c) - static_cast<float>(columns - 1) / 2) * spacing,
                           (static_cast<float>(rows - 1) / 2 - static_cast<float>(r)) * spacing, 0}};
            node.mesh.uvs.clear();
            doc.nodes.push_back(std::move(node));
        }
    return doc;
}

}  // namespace facet_test
