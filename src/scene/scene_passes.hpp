// facet scene: render_scene with render passes, for views.cpp (facet/views.hpp). In: the objects,
// the camera, the pass targets and each object's material id; out: the colour target and the
// passes, each object drawn as render_scene draws it, with its DrawPasses. Private to the library.
#pragma once

#include <cstdint>
#include <span>

#include "facet/passes.hpp"
#include "facet/scene.hpp"

namespace facet::detail {

struct ScenePasses {
    PassTargets targets;                  // of the target's size
    const std::uint32_t* material_ids;    // per object: its material's id (views.cpp numbers them); null: 0
    NormalSpace normal_space = NormalSpace::world;
};

// render_scene, writing `passes` too: instance i + 1 for object i.
DrawStats render_scene_passes(Renderer& renderer, Framebuffer& target, std::span<const ObjectView> objects,
                              const Camera& camera, const RenderSettings& settings, const ScenePasses& passes);

// Throws FacetError when an object's non-empty normals, colours, uvs or tangents are not as many as
// its positions (the shaders would read past their end): a caller's mistake, not bad geometry.
void require_aligned_arrays(const Scene& scene);

// What DrawPasses needs of the camera for a target of width x height: the depth mapping, the
// pixels' rays (range) and the normal pass's space.
void set_camera_passes(DrawPasses& out, const Camera& camera, int width, int height, NormalSpace space);

}  // namespace facet::detail
