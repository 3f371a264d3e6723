// facet scene: the lit mode's draw of one object (render_scene's Shading::lit). In: the object,
// its uniforms and the settings' environment, exposure and tone mapping. Out: the draw, with the
// shaders::Pbr variant its material and arrays call for. Not the other modes (scene.cpp).
#pragma once

#include "facet/passes.hpp"
#include "facet/scene.hpp"
#include "facet/shaders.hpp"

namespace facet::scene_detail {

// The PbrUniforms of a material (its maps only where the mesh has uvs to sample them with) under
// the settings' environment and display transform.
PbrUniforms pbr_uniforms(const Material& material, bool has_uvs, const RenderSettings& settings);

DrawStats draw_lit(Renderer& r, Framebuffer& target, const DrawState& state, const ObjectView& o,
                   const ShadingUniforms& u, const MeshArrays& arrays, const RenderSettings& settings,
                   const DrawPasses* passes);

}  // namespace facet::scene_detail
