// The fast-path tests' check: load_model (facet's own readers first) must give exactly the Scene the
// assimp path gives (io_detail::load_model_through_assimp), field by field and bit for bit, or the
// same error. Textures are compared by their pixels, and which objects share one texture; the lit
// mode's material fields (metallic-roughness, normal, occlusion and emissive maps) and tangents too.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "facet/model.hpp"
#include "io/load_paths.hpp"
#include "support/test_data.hpp"

namespace facet_test {

using namespace facet;

inline bool same_texture(const Texture* a, const Texture* b) {
    if (!a || !b) return a == b;
    return a->width() == b->width() && a->height() == b->height() && a->level(0).pixels == b->level(0).pixels;
}

inline std::vector<float> transform_of(const UvTransform& t) { return std::vector<float>(t.m, t.m + 6); }

// A texture map of the lit mode's materials: the same pixels, sampler and uv transform.
inline void expect_same_map(const TextureMap& a, const TextureMap& b, const char* which) {
    SCOPED_TRACE(which);
    EXPECT_TRUE(same_texture(a.texture.get(), b.texture.get()));
    EXPECT_EQ(a.sampler.wrap_u, b.sampler.wrap_u);
    EXPECT_EQ(a.sampler.wrap_v, b.sampler.wrap_v);
    EXPECT_EQ(a.sampler.filter, b.sampler.filter);
    EXPECT_EQ(bits_of(transform_of(a.transform)), bits_of(transform_of(b.transform)));
}

inline void expect_same_scene(const Result<LoadedModel>& fast, const Result<LoadedModel>& assimp) {
    ASSERT_EQ(fast.ok(), assimp.ok()) << (fast.ok() ? assimp.error().message : fast.error().message);
    if (!fast.ok()) {
        EXPECT_EQ(fast.error().code, assimp.error().code);
        EXPECT_EQ(fast.error().message, assimp.error().message);
        return;
    }
    EXPECT_EQ(fast->warnings, assimp->warnings);
    ASSERT_EQ(fast->scene.objects.size(), assimp->scene.objects.size());
    for (std::size_t o = 0; o < fast->scene.objects.size(); ++o) {
        SCOPED_TRACE("object " + std::to_string(o));
        const SceneObject &a = fast->scene.objects[o], &b = assimp->scene.objects[o];
        EXPECT_EQ(bits_of(a.mesh.positions), bits_of(b.mesh.positions));
        EXPECT_EQ(bits_of(a.mesh.normals), bits_of(b.mesh.normals));
        EXPECT_EQ(bits_of(a.mesh.colours), bits_of(b.mesh.colours));
        EXPECT_EQ(bits_of(a.mesh.uvs), bits_of(b.mesh.uvs));
        EXPECT_EQ(a.mesh.indices, b.mesh.indices);
        EXPECT_EQ(bits_of(std::vector<Mat4>{a.model}), bits_of(std::vector<Mat4>{b.model}));
        EXPECT_EQ(bits_of(std::vector<Vec4>{a.material.base_colour}), bits_of(std::vector<Vec4>{b.material.base_colour}));
        EXPECT_TRUE(same_texture(a.material.base_colour_texture.get(), b.material.base_colour_texture.get()));
        for (std::size_t p = 0; p < o; ++p)
            EXPECT_EQ(a.material.base_colour_texture == fast->scene.objects[p].material.base_colour_texture,
                      b.material.base_colour_texture == assimp->scene.objects[p].material.base_colour_texture)
                << "texture sharing with object " << p;
        EXPECT_EQ(a.material.alpha_mode, b.material.alpha_mode);
        EXPECT_EQ(a.material.alpha_cutoff, b.material.alpha_cutoff);
        EXPECT_EQ(a.material.double_sided, b.material.double_sided);
        EXPECT_EQ(a.material.sampler.wrap_u, b.material.sampler.wrap_u);
        EXPECT_EQ(a.material.sampler.wrap_v, b.material.sampler.wrap_v);
        EXPECT_EQ(a.material.sampler.filter, b.material.sampler.filter);
        // The lit mode's fields (metallic-roughness, the maps, tangents).
        EXPECT_EQ(bits_of(a.mesh.tangents), bits_of(b.mesh.tangents));
        EXPECT_EQ(bits_of(transform_of(a.material.base_colour_transform)), bits_of(transform_of(b.material.base_colour_transform)));
        EXPECT_EQ(bits_of(std::vector<float>{a.material.metallic, a.material.roughness, a.material.normal_scale,
                                             a.material.occlusion_strength}),
                  bits_of(std::vector<float>{b.material.metallic, b.material.roughness, b.material.normal_scale,
                                             b.material.occlusion_strength}));
        EXPECT_EQ(bits_of(std::vector<Vec3>{a.material.emissive}), bits_of(std::vector<Vec3>{b.material.emissive}));
        EXPECT_EQ(a.material.unlit, b.material.unlit);
        expect_same_map(a.material.metallic_roughness_map, b.material.metallic_roughness_map, "metallic_roughness_map");
        expect_same_map(a.material.normal_map, b.material.normal_map, "normal_map");
        expect_same_map(a.material.occlusion_map, b.material.occlusion_map, "occlusion_map");
        expect_same_map(a.material.emissive_map, b.material.emissive_map, "emissive_map");
    }
    const Aabb fa = fast->scene.bounds(), ab = assimp->scene.bounds();
    EXPECT_EQ(bits_of(std::vector<Vec3>{fa.min, fa.max}), bits_of(std::vector<Vec3>{ab.min, ab.max}));
}

inline void expect_same_as_assimp(const std::string& path, const LoadOptions& options = {}) {
    SCOPED_TRACE(path);
    expect_same_scene(load_model(path, options), io_detail::load_model_through_assimp(path, options));
}


// `read` is a fast path's reader (bytes -> optional mesh): it takes the file or not, as `taken` says,
// and load_model gives the assimp path's Scene either way.
template <class Read>
void expect_read_as_told_and_same(const std::string& path, Read read, bool taken = true) {
    EXPECT_EQ(read(read_file(path)).has_value(), taken) << path;
    expect_same_as_assimp(path);
}

}  // namespace facet_test
