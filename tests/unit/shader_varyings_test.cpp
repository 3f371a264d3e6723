// The built-in shaders' varyings, declared once per shader (shaders::VaryingLayout): the layout's
// arithmetic, and every built-in shader's vertex() writing each varying it declares, and nothing
// else, where its layout says, with the mesh attribute the varying names, computed here from the
// attribute's definition. (Its fragment(), compiled vertex stage and SIMD kernels read the same
// layout; Isa.CompiledVertexStages* and CompiledVisiblePass.* compare those with vertex() and
// fragment() on every ISA.)
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "facet/shaders.hpp"

namespace {

using namespace facet;
using shaders::Varying;

using Full = shaders::VaryingLayout<Varying::uv, Varying::normal, Varying::position, Varying::colour>;
static_assert(Full::count == 12);
static_assert(Full::at(Varying::uv) == 0 && Full::at(Varying::normal) == 2 && Full::at(Varying::position) == 5 &&
              Full::at(Varying::colour) == 8);
static_assert(Full::through(Varying::uv) == 2 && Full::through(Varying::position) == 8);
using Reordered = shaders::VaryingLayout<Varying::colour, Varying::normal>;
static_assert(Reordered::count == 7 && Reordered::at(Varying::colour) == 0 && Reordered::at(Varying::normal) == 4 &&
              !Reordered::has(Varying::uv) && Reordered::at(Varying::position) == -1);
static_assert(shaders::VaryingLayout<>::count == 0 && !shaders::VaryingLayout<>::has(Varying::colour));
// Derivatives cover what the shaders read them of: the uv pair, and Flat's position.
static_assert(shaders::Textured::k_derivative_count == 2 && shaders::TextureUnlit::k_derivative_count == 2);
static_assert(shaders::Pbr::k_derivative_count == 2 && shaders::PbrNormalMapped::Layout::at(Varying::tangent) == 8 &&
              shaders::PbrNormalMapped::k_varyings == 16);
static_assert(shaders::Flat::k_derivative_count == 3 && shaders::Flat::Layout::at(Varying::position) == 0);

// The value of the attribute a varying names, for vertex 0 of `mesh` (MeshArrays' pointers may be null).
std::vector<float> attribute(Varying v, const MeshArrays& mesh, const ShadingUniforms& u) {
    switch (v) {
        case Varying::uv: {
            const Vec2 t = mesh.uvs ? mesh.uvs[0] : Vec2{};
            return {t.x, t.y};
        }
        case Varying::normal: {
            const Vec3 n = mesh.normals ? u.normal_to_world * mesh.normals[0] : Vec3{};
            return {n.x, n.y, n.z};
        }
        case Varying::position: {
            const Vec4 p = u.model * Vec4(mesh.positions[0], 1);
            return {p.x, p.y, p.z};
        }
        case Varying::colour: {
            const Vec4 c = mesh.colours ? u.base_colour * mesh.colours[0] : u.base_colour;
            return {c.x, c.y, c.z, c.w};
        }
        case Varying::tangent: {
            if (!mesh.tangents) return {0, 0, 0, 1};
            const Vec4 t = mesh.tangents[0];
            const Vec4 m = u.model * Vec4(t.xyz(), 0);  // a direction: the model's 3x3
            return {m.x, m.y, m.z, t.w * u.handedness};
        }
    }
    return {};
}

// Every float vertex() writes is the declared varying's at its slot; every slot is some varying's.
template <class S>
void expect_vertex_writes_its_layout(const MeshArrays& mesh, const ShadingUniforms& u) {
    using Layout = typename S::Layout;
    constexpr int N = S::k_varyings;
    static_assert(N == Layout::count);
    S shader{};
    shader.mesh = mesh;
    shader.u = u;
    Varyings<N> out;
    for (int k = 0; k < N; ++k) out[k] = -12345.0f;  // what no attribute here is
    const Vec4 clip = shader.vertex(0, out);
    const Vec4 expected_clip = u.clip_from_object * Vec4(mesh.positions[0], 1);
    EXPECT_EQ(std::memcmp(&clip, &expected_clip, sizeof(Vec4)), 0);
    int written = 0;
    for (Varying v : {Varying::uv, Varying::normal, Varying::position, Varying::colour, Varying::tangent}) {
        if (!Layout::has(v)) continue;
        const std::vector<float> want = attribute(v, mesh, u);
        ASSERT_EQ(static_cast<int>(want.size()), shaders::varying_width(v));
        for (std::size_t k = 0; k < want.size(); ++k)
            EXPECT_EQ(out[Layout::at(v) + static_cast<int>(k)], want[k])
                << "varying " << static_cast<int>(v) << ", float " << k;
        written += static_cast<int>(want.size());
    }
    EXPECT_EQ(written, N);
    for (int k = 0; k < N; ++k) EXPECT_NE(out[k], -12345.0f) << "slot " << k << " was not written";
}

template <class S>
class ShaderVaryings : public ::testing::Test {};
using BuiltInShaders =
    ::testing::Types<shaders::VertexColour, shaders::Flat, shaders::Lambert, shaders::LambertBaseColour,
                     shaders::BlinnPhong, shaders::BlinnPhongBaseColour, shaders::Textured, shaders::TexturedOpaque,
                     shaders::TextureUnlit, shaders::TextureUnlitOpaque, shaders::Normals, shaders::Mask, shaders::Pbr,
                     shaders::PbrMasked, shaders::PbrNormalMapped, shaders::PbrNormalMappedMasked>;
TYPED_TEST_SUITE(ShaderVaryings, BuiltInShaders);

TYPED_TEST(ShaderVaryings, VertexWritesItsLayout) {
    const std::vector<Vec3> positions{{0.25f, -1.5f, 2.0f}}, normals{{0.3f, 0.8f, -0.5f}};
    const std::vector<Vec4> colours{{0.2f, 0.4f, 0.6f, 0.8f}};
    const std::vector<Vec2> uvs{{0.125f, 0.75f}};
    const std::vector<Vec4> tangents{{0.6f, -0.8f, 0.0f, -1.0f}};
    ShadingUniforms u;
    u.handedness = -1;  // a mirroring model turns the tangents' side over
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            u.model(r, c) = 0.5f + static_cast<float>(r * 4 + c) * 0.25f;
            u.clip_from_object(r, c) = 1.0f - static_cast<float>(r + 2 * c) * 0.125f;
        }
    for (int c = 0; c < 3; ++c) u.normal_to_world.col[c] = {0.5f + static_cast<float>(c), -0.25f, 0.75f};
    u.base_colour = {0.5f, 0.25f, 2.0f, 0.5f};
    expect_vertex_writes_its_layout<TypeParam>({positions.data(), normals.data(), colours.data(), uvs.data(), tangents.data()}, u);
    // Positions alone: the attributes' defaults.
    expect_vertex_writes_its_layout<TypeParam>({positions.data(), nullptr, nullptr, nullptr, nullptr}, u);
}

// What fragment() reads is where vertex() wrote it: a varying that is the same at all three vertices
// interpolates to itself, so fragment() sees what vertex() wrote, and an unlit shader gives back the
// attribute its varying names.
template <class S>
Vec4 fragment_of_vertex_0(const MeshArrays& mesh) {
    const S shader{mesh, ShadingUniforms{}};  // identity matrices, white base colour
    FragmentIn<S::k_varyings> in;
    shader.vertex(0, in.v);
    return shader.fragment(in);
}

TEST(ShaderVaryings, UnlitShadersReadTheVaryingTheirVertexWrote) {
    const std::vector<Vec3> positions{{0, 0, 0}}, normals{{0.0f, 0.6f, 0.8f}};
    const std::vector<Vec4> colours{{0.2f, 0.4f, 0.6f, 0.8f}};
    const MeshArrays mesh{positions.data(), normals.data(), colours.data(), nullptr};
    const Vec4 c = fragment_of_vertex_0<shaders::VertexColour>(mesh);
    EXPECT_EQ(c.x, 0.2f);
    EXPECT_EQ(c.y, 0.4f);
    EXPECT_EQ(c.z, 0.6f);
    EXPECT_EQ(c.w, 0.8f);
    const Vec4 n = fragment_of_vertex_0<shaders::Normals>(mesh);  // 0.5 + 0.5 n
    EXPECT_FLOAT_EQ(n.x, 0.5f);
    EXPECT_FLOAT_EQ(n.y, 0.8f);
    EXPECT_FLOAT_EQ(n.z, 0.9f);
}

}  // namespace
