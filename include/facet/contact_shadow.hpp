// facet: a soft contact shadow on the ground under a model, as product viewers show one (the lit
// mode's thumbnails). In: the objects and a renderer. Out: a black, unlit, alpha-blended quad on
// the ground whose texture's alpha is the shadow, to draw after the objects (render_scene over
// ObjectViews). Not a shadow of the environment's lights: it darkens where the model is near the
// ground, seen from below, whatever the light.
#pragma once

#include <optional>
#include <span>

#include "facet/api.hpp"
#include "facet/mesh.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

FACET_API_BEGIN
namespace facet {

struct ContactShadow {
    Mesh mesh;          // the quad, a hair below the objects' lowest y, normals +Y, uvs into the texture
    Material material;  // black, unlit, alpha-blended, double-sided; base_colour_texture's alpha is the shadow
    ObjectView view() const;  // to draw it (the ContactShadow must outlive the view)
};

// The rule (README, "Contact shadow"): the objects' depth seen from below, orthographic, over a
// square around their bounds (each side the larger horizontal extent plus a quarter of the largest
// extent), `k_resolution` texels square; a texel whose nearest surface is h above the lowest point
// of the bounds, within a band of a quarter of the largest extent, darkens by (1 - h / band)^2; blurred
// by three box filters of radius k_resolution / 32 each way; alpha = opacity x that. Nothing for
// empty bounds or opacity <= 0.
inline constexpr int k_contact_shadow_resolution = 128;
std::optional<ContactShadow> make_contact_shadow(Renderer& renderer, std::span<const ObjectView> objects, float opacity);

}  // namespace facet
FACET_API_END
