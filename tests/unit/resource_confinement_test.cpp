// Untrusted files (issue 20, docs/RELIABILITY.md): a model may read only the files of its own folder
// and the --resource-dir folders. Each test puts a red "private" image (or a red MTL, or a glTF
// buffer) in a folder beside the model's, references it the way a format allows (a relative "..",
// an absolute path, a "file://" URI, a symbolic link inside the folder pointing out) and checks that
// the render of the model never shows red and that the warning names the model and the reference;
// then that --resource-dir (LoadOptions::resource_dirs) lets the same reference through, which shows
// the reference itself works and the red would have appeared.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "facet/io.hpp"
#include "facet/model.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::run_facet;
using facet_test::write_file;

// A folder `model` for the model files and a folder `private` beside it, holding private.png (4x4,
// pure red), red.mtl (a red material) and quad.bin (a glTF buffer: a quad filling the view).
struct Folders {
    fs::path root, model, other;
};

Folders make_folders(const std::string& name) {
    Folders f;
    f.root = facet_test::test_temp_dir("facet_resources_" + name);
    f.model = f.root / "model";
    f.other = f.root / "private";
    fs::create_directories(f.model);
    fs::create_directories(f.other);
    facet::Image red{4, 4, std::vector<facet::Rgba8>(16, facet::Rgba8{255, 0, 0, 255})};
    EXPECT_TRUE(facet::write_png((f.other / "private.png").string(), red).ok());
    write_file(f.other / "red.mtl", "newmtl m\nKd 1 0 0\n");
    return f;
}

// A quad over the whole view, with uvs, using material "m" of `mtllib`.
std::string quad_obj(const std::string& mtllib) {
    return "mtllib " + mtllib +
           "\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\n"
           "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
}

std::string white_mtl_with_texture(const std::string& texture) { return "newmtl m\nKd 1 1 1\nmap_Kd " + texture + "\n"; }

// The quad's glTF buffer: positions, uvs and indices.
std::string quad_buffer() {
    const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float uvs[] = {0, 1, 1, 1, 1, 0, 0, 0};
    const std::uint16_t indices[] = {0, 1, 2, 0, 2, 3, 0, 0};  // padded to 4 bytes
    std::string b(reinterpret_cast<const char*>(positions), sizeof positions);
    b.append(reinterpret_cast<const char*>(uvs), sizeof uvs);
    b.append(reinterpret_cast<const char*>(indices), sizeof indices);
    return b;
}

std::string quad_gltf(const std::string& buffer_uri, const std::string& image_uri) {
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
"textures":[{"source":0}],"images":[{"uri":")" +
           image_uri + R"("}],"buffers":[{"uri":")" + buffer_uri + R"(","byteLength":96}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":32},
{"buffer":0,"byteOffset":80,"byteLength":12}],
"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-1,-1,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"},{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}]})";
}

// A COLLADA quad whose diffuse colour is the texture `image` names.
std::string quad_dae(const std::string& image) {
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><up_axis>Y_UP</up_axis></asset>
<library_images><image id="img"><init_from>)" +
           image + R"(</init_from></image></library_images>
<library_effects><effect id="fx"><profile_COMMON>
<newparam sid="surf"><surface type="2D"><init_from>img</init_from></surface></newparam>
<newparam sid="samp"><sampler2D><source>surf</source></sampler2D></newparam>
<technique sid="common"><lambert><diffuse><texture texture="samp" texcoord="UV"/></diffuse></lambert></technique>
</profile_COMMON></effect></library_effects>
<library_materials><material id="mat"><instance_effect url="#fx"/></material></library_materials>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="12">-1 -1 0 1 -1 0 1 1 0 -1 1 0</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<source id="t"><float_array id="ta" count="8">0 0 1 0 1 1 0 1</float_array>
<technique_common><accessor source="#ta" count="4" stride="2"><param name="S" type="float"/><param name="T" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="2" material="m"><input semantic="VERTEX" source="#v" offset="0"/><input semantic="TEXCOORD" source="#t" offset="0" set="0"/><p>0 1 2 0 2 3</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"><bind_material><technique_common>
<instance_material symbol="m" target="#mat"><bind_vertex_input semantic="UV" input_semantic="TEXCOORD" input_set="0"/></instance_material>
</technique_common></bind_material></instance_geometry></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
}

// The quad covers 400 of the 32x32 pixels (automatic framing fits its bounding sphere in the view).
constexpr int k_quad_pixels = 300;

// Pixels of the private image's colour (pure red: no shading mode or fallback makes it).
int red_pixels(const fs::path& png) {
    const facet_test::DecodedPng image = facet_test::decode_png(png);
    EXPECT_TRUE(image.ok()) << png << ": " << image.error;
    int n = 0;
    for (const facet::Rgba8& p : image.rgba) n += p.r >= 200 && p.g <= 40 && p.b <= 40;
    return n;
}

struct Rendered {
    facet_test::CliRun run;
    int red = 0;
};

// `facet render` (or, with `thumbs`, `facet thumbs`) of the model, unlit texture shading so that the
// texture's colour reaches the pixels as it is.
Rendered render(const fs::path& model, const std::vector<std::string>& extra = {}, bool thumbs = false) {
    const fs::path out_dir = model.parent_path().parent_path() / "out";
    fs::create_directories(out_dir);
    const fs::path out = thumbs ? out_dir / (model.filename().string() + ".png") : out_dir / "render.png";
    fs::remove(out);
    std::vector<std::string> args = thumbs ? std::vector<std::string>{"thumbs", model.string(), "-o", out_dir.string(), "--size", "32"}
                                           : std::vector<std::string>{"render", model.string(), "-o", out.string(), "--size", "32x32"};
    for (const char* a : {"--shading", "texture"}) args.push_back(a);
    args.insert(args.end(), extra.begin(), extra.end());
    Rendered r;
    r.run = run_facet(args);
    if (r.run.exit_code == 0) r.red = red_pixels(out);
    return r;
}

// The model renders without a pixel of the private colour, with a warning naming the model and the
// reference; with --resource-dir naming the private folder, the private colour covers the view.
void expect_refused_then_allowed(const Folders& f, const fs::path& model, const std::string& reference) {
    SCOPED_TRACE(model.filename().string() + " -> " + reference);
    const Rendered refused = render(model);
    ASSERT_EQ(refused.run.exit_code, 0) << refused.run.err;
    EXPECT_EQ(refused.red, 0) << "the private image reached the output";
    EXPECT_NE(refused.run.err.find("warning: " + model.string() + ": "), std::string::npos) << refused.run.err;
    EXPECT_NE(refused.run.err.find("refused to read '" + reference + "'"), std::string::npos) << refused.run.err;
    EXPECT_NE(refused.run.err.find("outside the model's folder"), std::string::npos) << refused.run.err;

    const Rendered allowed = render(model, {"--resource-dir", f.other.string()});
    ASSERT_EQ(allowed.run.exit_code, 0) << allowed.run.err;
    EXPECT_GT(allowed.red, k_quad_pixels) << "the reference itself does not work: the test shows nothing";
    EXPECT_EQ(allowed.run.err.find("refused"), std::string::npos) << allowed.run.err;
}

TEST(ResourceConfinement, ObjTexturesOutsideTheFolderAreRefused) {
    const Folders f = make_folders("obj_texture");
    fs::create_directories(f.model / "sub");
    const std::string absolute = (f.other / "private.png").string();
    int i = 0;
    for (const std::string& reference : std::vector<std::string>{"../private/private.png", absolute, "sub/../../private/private.png"}) {
        const std::string name = "t" + std::to_string(i++);
        write_file(f.model / (name + ".mtl"), white_mtl_with_texture(reference));
        const fs::path model = write_file(f.model / (name + ".obj"), quad_obj(name + ".mtl"));
        expect_refused_then_allowed(f, model, reference);
    }
}

TEST(ResourceConfinement, ObjMtlOutsideTheFolderIsRefused) {
    const Folders f = make_folders("obj_mtl");
    const fs::path model = write_file(f.model / "quad.obj", quad_obj("../private/red.mtl"));
    const Rendered refused = render(model);
    ASSERT_EQ(refused.run.exit_code, 0) << refused.run.err;
    EXPECT_EQ(refused.red, 0) << "the private material reached the output";
    EXPECT_NE(refused.run.err.find("warning: " + model.string() + ": refused to read '"), std::string::npos) << refused.run.err;
    EXPECT_NE(refused.run.err.find("red.mtl'"), std::string::npos) << refused.run.err;
    const Rendered allowed = render(model, {"--resource-dir", f.other.string()});
    ASSERT_EQ(allowed.run.exit_code, 0) << allowed.run.err;
    EXPECT_GT(allowed.red, k_quad_pixels) << allowed.run.err;
}

TEST(ResourceConfinement, GltfImageUrisOutsideTheFolderAreRefused) {
    const Folders f = make_folders("gltf_image");
    write_file(f.model / "quad.bin", quad_buffer());
    const std::string absolute = (f.other / "private.png").string();
    int i = 0;
    for (const std::string& uri : std::vector<std::string>{"../private/private.png", absolute, "file://" + absolute}) {
        const fs::path model = write_file(f.model / ("quad" + std::to_string(i++) + ".gltf"), quad_gltf("quad.bin", uri));
        expect_refused_then_allowed(f, model, uri);
    }
}

TEST(ResourceConfinement, GltfBufferOutsideTheFolderIsRefused) {
    const Folders f = make_folders("gltf_buffer");
    write_file(f.other / "quad.bin", quad_buffer());
    const facet::Image red{4, 4, std::vector<facet::Rgba8>(16, facet::Rgba8{255, 0, 0, 255})};
    ASSERT_TRUE(facet::write_png((f.model / "red.png").string(), red).ok());
    const fs::path model = write_file(f.model / "quad.gltf", quad_gltf("../private/quad.bin", "red.png"));
    // The buffer holds the geometry: without it there is nothing to render, and the error says why.
    const Rendered refused = render(model);
    EXPECT_EQ(refused.run.exit_code, 1);
    EXPECT_NE(refused.run.err.find(model.string() + ": cannot be read as a model"), std::string::npos) << refused.run.err;
    EXPECT_NE(refused.run.err.find("refused to read '"), std::string::npos) << refused.run.err;
    EXPECT_NE(refused.run.err.find("quad.bin'"), std::string::npos) << refused.run.err;
    const Rendered allowed = render(model, {"--resource-dir", f.other.string()});
    ASSERT_EQ(allowed.run.exit_code, 0) << allowed.run.err;
    EXPECT_GT(allowed.red, k_quad_pixels);
}

// assimp's COLLADA reader, one of the formats facet reads through assimp only: its image paths
// reach facet's texture loading as the file wrote them (a "file://" URI without its scheme).
TEST(ResourceConfinement, ColladaTexturesOutsideTheFolderAreRefused) {
    const Folders f = make_folders("collada");
    const std::string absolute = (f.other / "private.png").string();
    int i = 0;
    for (const auto& [image, reference] : std::vector<std::pair<std::string, std::string>>{
             {"../private/private.png", "../private/private.png"}, {absolute, absolute}, {"file://" + absolute, absolute}}) {
        const fs::path model = write_file(f.model / ("quad" + std::to_string(i++) + ".dae"), quad_dae(image));
        expect_refused_then_allowed(f, model, reference);
    }
}

TEST(ResourceConfinement, SymbolicLinksPointingOutAreRefused) {
    const Folders f = make_folders("links");
    fs::create_directories(f.model / "sub");
    fs::create_symlink(f.other / "private.png", f.model / "sub" / "link.png");  // a file link
    fs::create_directory_symlink(f.other, f.model / "linked");                 // a folder link
    int i = 0;
    for (const std::string reference : {"sub/link.png", "linked/private.png"}) {
        const std::string name = "l" + std::to_string(i++);
        write_file(f.model / (name + ".mtl"), white_mtl_with_texture(reference));
        const fs::path model = write_file(f.model / (name + ".obj"), quad_obj(name + ".mtl"));
        expect_refused_then_allowed(f, model, reference);
    }
}

// Inside the folder everything still works: subfolders, "..", links that stay inside, a data URI.
TEST(ResourceConfinement, ReferencesInsideTheFolderAreRead) {
    const Folders f = make_folders("inside");
    fs::create_directories(f.model / "textures");
    fs::copy_file(f.other / "private.png", f.model / "textures" / "red.png");
    fs::create_symlink("textures/red.png", f.model / "inner_link.png");
    int i = 0;
    for (const std::string reference : {"textures/red.png", "textures/../textures/red.png", "inner_link.png"}) {
        const std::string name = "i" + std::to_string(i++);
        write_file(f.model / (name + ".mtl"), white_mtl_with_texture(reference));
        const fs::path model = write_file(f.model / (name + ".obj"), quad_obj(name + ".mtl"));
        const Rendered r = render(model);
        ASSERT_EQ(r.run.exit_code, 0) << r.run.err;
        EXPECT_GT(r.red, k_quad_pixels) << reference << ": " << r.run.err;
        EXPECT_EQ(r.run.err.find("warning"), std::string::npos) << r.run.err;
    }
    write_file(f.model / "quad.bin", quad_buffer());
    const std::string data_uri = "data:image/png;base64," + facet_test::base64(facet_test::read_file(f.other / "private.png"));
    const Rendered embedded = render(write_file(f.model / "data_uri.gltf", quad_gltf("quad.bin", data_uri)));
    ASSERT_EQ(embedded.run.exit_code, 0) << embedded.run.err;
    EXPECT_GT(embedded.red, k_quad_pixels) << embedded.run.err;
}

TEST(ResourceConfinement, ThumbsTakeResourceDirsToo) {
    const Folders f = make_folders("thumbs");
    write_file(f.model / "quad.mtl", white_mtl_with_texture("../private/private.png"));
    const fs::path model = write_file(f.model / "quad.obj", quad_obj("quad.mtl"));
    const Rendered refused = render(model, {}, /*thumbs=*/true);
    ASSERT_EQ(refused.run.exit_code, 0) << refused.run.err;
    EXPECT_EQ(refused.red, 0);
    EXPECT_NE(refused.run.err.find("refused to read '../private/private.png'"), std::string::npos) << refused.run.err;
    // Repeatable: the first folder is not the one that holds the texture.
    const Rendered allowed = render(model, {"--resource-dir", f.model.string(), "--resource-dir", f.other.string()}, true);
    ASSERT_EQ(allowed.run.exit_code, 0) << allowed.run.err;
    EXPECT_GT(allowed.red, k_quad_pixels);
}

TEST(ResourceConfinement, ResourceDirMustBeAFolder) {
    const Folders f = make_folders("usage");
    const fs::path model = write_file(f.model / "quad.obj", quad_obj("none.mtl"));
    const facet_test::CliRun r = run_facet({"render", model.string(), "-o", (f.root / "x.png").string(), "--resource-dir",
                                            (f.root / "no_such_folder").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--resource-dir '" + (f.root / "no_such_folder").string() + "' is not a directory"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(f.root / "x.png"));
}

// facet view loads with the same options (it prints them like the other commands).
TEST(ResourceConfinement, ViewTakesResourceDirs) {
    const Folders f = make_folders("view");
    const facet_test::CliRun r = run_facet({"view", "--print-config", "--resource-dir", f.other.string(), "--resource-dir",
                                            f.model.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\nresource-dirs = " + f.other.string() + ", " + f.model.string() + "\n"), std::string::npos) << r.out;
    EXPECT_NE(run_facet({"view", "--print-config"}).out.find("\nresource-dirs = (only the model's folder)\n"), std::string::npos);
}

// The library: LoadOptions::resource_dirs, for load_model and load_model_isolated alike.
TEST(ResourceConfinement, LoadOptionsCarryTheResourceDirs) {
    const Folders f = make_folders("library");
    write_file(f.model / "quad.mtl", white_mtl_with_texture("../private/private.png"));
    const std::string model = write_file(f.model / "quad.obj", quad_obj("quad.mtl"));
    facet::LoadOptions allowed;
    allowed.resource_dirs = {f.other.string()};
    for (bool isolated : {false, true}) {
        SCOPED_TRACE(isolated ? "load_model_isolated" : "load_model");
        auto load = [&](const facet::LoadOptions& o) { return isolated ? facet::load_model_isolated(model, o) : facet::load_model(model, o); };
        const facet::Result<facet::LoadedModel> refused = load({});
        ASSERT_TRUE(refused.ok()) << refused.error().message;
        ASSERT_EQ(refused->scene.objects.size(), 1u);
        EXPECT_EQ(refused->scene.objects[0].material.base_colour_texture, nullptr);
        ASSERT_EQ(refused->warnings.size(), 1u);
        EXPECT_EQ(refused->warnings[0].rfind(model + ": texture '../private/private.png' not used", 0), 0u) << refused->warnings[0];
        const facet::Result<facet::LoadedModel> read = load(allowed);
        ASSERT_TRUE(read.ok()) << read.error().message;
        ASSERT_NE(read->scene.objects[0].material.base_colour_texture, nullptr);
        EXPECT_TRUE(read->warnings.empty());
    }
}

}  // namespace
