// facet scene: the lit mode's shader choice and uniforms (lit_shading.hpp).
#include "scene/lit_shading.hpp"

namespace facet::scene_detail {
namespace {

MapBinding bind(const TextureMap& map, bool has_uvs) {
    if (!has_uvs || !map.texture) return {};
    return {map.texture.get(), map.sampler, map.transform, !map.transform.is_identity()};
}

template <class S>
DrawStats draw_with(Renderer& r, Framebuffer& target, const DrawState& state, const ObjectView& o, const S& shader,
                    const DrawPasses* passes) {
    return r.draw(target, state, DrawInput{o.vertex_count, o.indices}, shader, passes);
}

}  // namespace

PbrUniforms pbr_uniforms(const Material& m, bool has_uvs, const RenderSettings& settings) {
    PbrUniforms p;
    p.metallic = m.metallic;
    p.roughness = m.roughness;
    p.normal_scale = m.normal_scale;
    p.occlusion_strength = m.occlusion_strength;
    p.emissive = m.emissive;
    p.base_colour = bind({m.base_colour_texture, m.sampler, m.base_colour_transform}, has_uvs);
    p.metallic_roughness = bind(m.metallic_roughness_map, has_uvs);
    p.normal = bind(m.normal_map, has_uvs);
    p.occlusion = bind(m.occlusion_map, has_uvs);
    p.emissive_map = bind(m.emissive_map, has_uvs);
    p.alpha_cutoff = m.alpha_mode == AlphaMode::mask ? m.alpha_cutoff : -1.0f;
    p.unlit = m.unlit;
    p.environment = settings.environment ? settings.environment.get() : Environment::studio().get();
    p.exposure = settings.exposure;
    p.tone_mapping = settings.tone_mapping;
    return p;
}

DrawStats draw_lit(Renderer& r, Framebuffer& target, const DrawState& state, const ObjectView& o,
                   const ShadingUniforms& u, const MeshArrays& arrays, const RenderSettings& settings,
                   const DrawPasses* passes) {
    // Without normals the face normals of the flat mode stand in.
    if (!arrays.normals) return draw_with(r, target, state, o, shaders::Flat{arrays, u}, passes);
    const PbrUniforms p = pbr_uniforms(*o.material, arrays.uvs != nullptr, settings);
    const bool masked = o.material->alpha_mode == AlphaMode::mask;
    // Blended and unlit (the contact shadow): the same colours from fewer varyings, and a SIMD kernel.
    if (state.blend == Blend::alpha && p.unlit && !masked &&
        (!p.base_colour.texture || p.base_colour.sampler.filter != Filter::trilinear))
        return draw_with(r, target, state, o, shaders::PbrUnlitBlended{arrays, u, p}, passes);
    if (p.normal.texture && arrays.tangents) {
        if (masked) return draw_with(r, target, state, o, shaders::PbrNormalMappedMasked{arrays, u, p}, passes);
        return draw_with(r, target, state, o, shaders::PbrNormalMapped{arrays, u, p}, passes);
    }
    if (masked) return draw_with(r, target, state, o, shaders::PbrMasked{arrays, u, p}, passes);
    return draw_with(r, target, state, o, shaders::Pbr{arrays, u, p}, passes);
}

}  // namespace facet::scene_detail
