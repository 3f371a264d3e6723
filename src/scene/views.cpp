// facet scene: views of a scene with render passes (facet/views.hpp): the pass names, the request's
// checks, each view rendered (colour by supersampled and jittered frames with the contact shadow,
// the surface passes at 1x), alpha from the samples' depth, the material ids, the cameras of many
// views and the camera rigs. Not the files: the command line writes them.
#include "facet/views.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <string>

#include "math/portable_trig.hpp"
#include "scene/scene_passes.hpp"

namespace facet {
namespace {

constexpr const char* k_pass_names[k_pass_count] = {"color",    "alpha",    "depth",     "range", "normal",
                                                    "instance", "material", "primitive", "uv"};

[[noreturn]] void bad_request(const std::string& message) {
    throw FacetError(Error{ErrorCode::invalid_argument, "ViewRenderer::render: " + message});
}

void check(const ViewRequest& r, std::size_t cameras, std::span<const PassImages> out) {
    if (r.width < 1 || r.height < 1 || r.width > k_max_target_size || r.height > k_max_target_size)
        bad_request("the size must be 1.." + std::to_string(k_max_target_size) + " per side, got " +
                    std::to_string(r.width) + "x" + std::to_string(r.height));
    if (r.ssaa < 1 || r.ssaa > 8) bad_request("ssaa must be 1..8, got " + std::to_string(r.ssaa));
    if (antialias_offsets(r.aa).empty()) bad_request("aa must be 1, 2, 4 or 8, got " + std::to_string(r.aa));
    if (static_cast<long>(r.width) * r.ssaa > k_max_target_size || static_cast<long>(r.height) * r.ssaa > k_max_target_size)
        bad_request("the size times ssaa must stay within " + std::to_string(k_max_target_size));
    if (r.passes.empty()) bad_request("no pass asked for");
    if (out.size() != cameras)
        bad_request(std::to_string(cameras) + " cameras but " + std::to_string(out.size()) + " sets of images");
    for (const PassImages& o : out) {
        const PassTargets& p = o.passes;
        const void* pointers[k_pass_count] = {o.colour,   p.alpha,    p.depth,     p.range, p.normal,
                                              p.instance, p.material, p.primitive, p.uv};
        for (Pass pass : k_all_passes)
            if (r.passes.has(pass) && !pointers[static_cast<int>(pass)])
                bad_request(std::string("the ") + pass_name(pass) + " pass is asked for but has no image");
    }
}

// Adds to each pixel's count the samples a surface covers: where the draw wrote depth (the clear
// value is 1, which the depth test never lets a surface write; blended surfaces write none).
void count_covered(const Framebuffer& samples, int factor, std::uint16_t* covered) {
    const int w = samples.width() / factor, h = samples.height() / factor;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int n = 0;
            for (int sy = 0; sy < factor; ++sy)
                for (int sx = 0; sx < factor; ++sx) n += samples.depth(x * factor + sx, y * factor + sy) < 1.0f;
            std::uint16_t& c = covered[static_cast<std::size_t>(y) * w + x];
            c = static_cast<std::uint16_t>(c + n);
        }
}

bool same_material(const Material& a, const Material& b) {
    return a.base_colour == b.base_colour && a.base_colour_texture == b.base_colour_texture &&
           a.sampler.wrap_u == b.sampler.wrap_u && a.sampler.wrap_v == b.sampler.wrap_v &&
           a.sampler.filter == b.sampler.filter && a.alpha_mode == b.alpha_mode &&
           a.alpha_cutoff == b.alpha_cutoff && a.double_sided == b.double_sided;
}

// splitmix64: a small generator whose sequence is fixed by its definition, on every platform.
std::uint64_t next_random(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
double unit_random(std::uint64_t& state) { return static_cast<double>(next_random(state) >> 11) * 0x1.0p-53; }

ViewSpec looking_from(const ViewSpec& base, double azimuth, double elevation) {
    ViewSpec v = base;
    v.azimuth = static_cast<float>(azimuth);
    v.elevation = static_cast<float>(elevation);
    return v;
}

// A whole number in 1..max from `text`, or nothing.
std::optional<long long> parse_count(std::string_view text, long long max) {
    if (text.empty() || text.size() > 18) return std::nullopt;
    long long n = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        n = n * 10 + (c - '0');
    }
    if (n < 1 || n > max) return std::nullopt;
    return n;
}

}  // namespace

const char* pass_name(Pass pass) { return k_pass_names[static_cast<int>(pass)]; }

Result<PassSet> parse_passes(std::string_view list) {
    auto known = [] {
        std::string s;
        for (Pass p : k_all_passes) {
            if (!s.empty()) s += ", ";
            s += pass_name(p);
        }
        return s;
    };
    PassSet set;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t end = std::min(list.find(',', start), list.size());
        const std::string_view name = list.substr(start, end - start);
        const auto* found = std::find_if(k_all_passes.begin(), k_all_passes.end(), [&](Pass p) { return name == pass_name(p); });
        if (name.empty()) return Error{ErrorCode::invalid_argument, "an empty pass name in '" + std::string(list) + "' (known: " + known() + ")"};
        if (found == k_all_passes.end())
            return Error{ErrorCode::invalid_argument, "unknown pass '" + std::string(name) + "' (known: " + known() + ")"};
        if (set.has(*found)) return Error{ErrorCode::invalid_argument, "the pass '" + std::string(name) + "' is named twice"};
        set.add(*found);
        start = end + 1;
    }
    return set;
}

std::string to_string(PassSet passes) {
    std::string s;
    for (Pass p : k_all_passes)
        if (passes.has(p)) {
            if (!s.empty()) s += ',';
            s += pass_name(p);
        }
    return s;
}

PassImages ViewImages::images() {
    auto at = [](auto& v) { return v.empty() ? nullptr : v.data(); };
    return {at(colour), {at(alpha), at(depth), at(range), at(normal), at(instance), at(material), at(primitive), at(uv)}};
}

void material_ids(std::span<const ObjectView> objects, std::vector<std::uint32_t>& ids,
                  std::vector<const Material*>& distinct) {
    ids.resize(objects.size());
    distinct.clear();
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const Material& m = *objects[i].material;
        std::size_t k = 0;
        while (k < distinct.size() && !same_material(*distinct[k], m)) ++k;
        if (k == distinct.size()) distinct.push_back(&m);
        ids[i] = static_cast<std::uint32_t>(k + 1);
    }
}

ViewRenderer::ViewRenderer(RendererConfig config) : renderer_(config) {}

ViewRenderer::~ViewRenderer() = default;

namespace {

Framebuffer& sized(std::optional<Framebuffer>& fb, int w, int h) {
    if (!fb || fb->width() != w || fb->height() != h) fb.emplace(w, h);
    return *fb;
}

// One drawing into `colour`; made so at first, without an array of its own (and nothing cleared:
// the draw clears both arrays).
Framebuffer& sized(std::optional<Framebuffer>& fb, int w, int h, Rgba8* colour) {
    if (!fb || fb->width() != w || fb->height() != h) fb.emplace(w, h, colour);
    else fb->use_colour_memory(colour);
    return *fb;
}

}  // namespace

void ViewRenderer::prepare(std::span<const ObjectView> objects, const ViewRequest& r) {
    if (r.passes.has(Pass::material)) material_ids(objects, material_ids_, materials_);
    shadow_.reset();
    if (r.contact_shadow > 0 && r.settings.shading == Shading::lit)
        shadow_ = make_contact_shadow(renderer_, objects, r.contact_shadow);
    if (!shadow_) return;
    shadowed_.assign(objects.begin(), objects.end());
    shadowed_.push_back(shadow_->view());
    if (r.passes.has(Pass::material)) material_ids_.push_back(0);  // read, never written: blended surfaces write no pass
}

DrawStats ViewRenderer::render_frames(std::span<const ObjectView> objects, const Camera& camera, const ViewRequest& r,
                                      Rgba8* colour, float* alpha, float* window_depth) {
    const int f = r.ssaa, n = r.aa;
    Framebuffer& samples = sized(samples_, r.width * f, r.height * f);
    const std::size_t pixels = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
    // The frames' colours averaged: two by a rounded mean of the output and the second frame, more by
    // a sum per channel. A frame is read in the samples themselves when there is nothing to filter.
    const bool averaged = n > 1 && colour;
    if (averaged && f > 1) frame_.resize(pixels);
    if (averaged && n > 2) colour_sum_.assign(pixels * 4, 0);  // 8 frames of 255 fit
    if (n > 1 && window_depth) frame_depth_.resize(pixels);
    if (alpha) covered_.assign(pixels, 0);
    RenderSettings settings = r.settings;
    const std::span<const Vec2> offsets = antialias_offsets(n);
    DrawStats first;
    for (int i = 0; i < n; ++i) {
        // In the target's pixels: a pixel of the image is f of them across.
        if (n > 1)
            settings.pixel_offset = {r.settings.pixel_offset.x + offsets[i].x * static_cast<float>(f),
                                     r.settings.pixel_offset.y + offsets[i].y * static_cast<float>(f)};
        const DrawStats s = render_scene(renderer_, samples, objects, camera, settings);
        if (i == 0) first = s;
        float* depth = window_depth && i > 0 ? frame_depth_.data() : window_depth;
        Rgba8* resolved = !averaged || (n == 2 && i == 0) ? colour : f > 1 ? frame_.data() : nullptr;
        if (resolved || depth) resolve_supersampled(samples, f, resolved, depth);
        if (averaged && resolved != colour) {
            // Channel by channel over the bytes (Rgba8 is four of them): loops the compiler vectorizes.
            const auto* bytes = reinterpret_cast<const std::uint8_t*>(resolved ? resolved : samples.colour_data());
            auto* out = reinterpret_cast<std::uint8_t*>(colour);
            if (n == 2)  // (sum + n / 2) >> 1, as below
                for (std::size_t k = 0; k < pixels * 4; ++k) out[k] = static_cast<std::uint8_t>((out[k] + bytes[k] + 1u) >> 1);
            else
                for (std::size_t k = 0; k < pixels * 4; ++k) colour_sum_[k] = static_cast<std::uint16_t>(colour_sum_[k] + bytes[k]);
        }
        if (depth && i > 0)
            for (std::size_t p = 0; p < pixels; ++p) window_depth[p] = std::min(window_depth[p], depth[p]);
        if (alpha) count_covered(samples, f, covered_.data());
    }
    if (averaged && n > 2) {
        // The rounded mean, (sum + n / 2) / n: n is a power of two (antialias_offsets), so a shift.
        const int shift = std::countr_zero(static_cast<unsigned>(n));
        auto* bytes = reinterpret_cast<std::uint8_t*>(colour);
        for (std::size_t k = 0; k < pixels * 4; ++k)
            bytes[k] = static_cast<std::uint8_t>((colour_sum_[k] + static_cast<unsigned>(n / 2)) >> shift);
    }
    if (alpha) {
        const float per_sample = 1.0f / static_cast<float>(f * f * n);
        for (std::size_t p = 0; p < pixels; ++p) alpha[p] = static_cast<float>(covered_[p]) * per_sample;
    }
    return first;
}

DrawStats ViewRenderer::render_view(std::span<const ObjectView> objects, const Camera& camera, const ViewRequest& r,
                                    const PassImages& out) {
    const PassSet passes = r.passes;
    // The contact shadow is seen only from above its ground.
    const bool shadow_seen = shadow_ && camera.position.y > shadow_->mesh.positions[0].y;
    const std::span<const ObjectView> drawn = shadow_seen ? std::span<const ObjectView>(shadowed_) : objects;
    // Only what was asked for: a pass left out costs nothing.
    detail::ScenePasses surface{.targets = {},
                                .material_ids = passes.has(Pass::material) ? material_ids_.data() : nullptr,
                                .normal_space = r.normal_space};
    PassTargets& t = surface.targets;
    if (passes.has(Pass::depth)) t.depth = out.passes.depth;
    if (passes.has(Pass::range)) t.range = out.passes.range;
    if (passes.has(Pass::normal)) t.normal = out.passes.normal;
    if (passes.has(Pass::instance)) t.instance = out.passes.instance;
    if (passes.has(Pass::material)) t.material = out.passes.material;
    if (passes.has(Pass::primitive)) t.primitive = out.passes.primitive;
    if (passes.has(Pass::uv)) t.uv = out.passes.uv;
    Rgba8* colour = passes.has(Pass::colour) ? out.colour : nullptr;
    float* alpha = passes.has(Pass::alpha) ? out.passes.alpha : nullptr;

    if (r.ssaa == 1 && r.aa == 1) {
        // One draw per object for everything, colour straight into the caller's image. (direct_ keeps
        // pointing there afterwards: going back to memory of its own would allocate at every view.)
        Framebuffer& fb = colour ? sized(direct_, r.width, r.height, colour) : sized(target_, r.width, r.height);
        t.alpha = alpha;
        const DrawStats stats = passes.needs_surface() || alpha
                                    ? detail::render_scene_passes(renderer_, fb, drawn, camera, r.settings, surface)
                                    : render_scene(renderer_, fb, drawn, camera, r.settings);
        if (out.window_depth) resolve_supersampled(fb, 1, nullptr, out.window_depth);
        return stats;
    }
    DrawStats stats;
    if (colour || alpha || out.window_depth) stats = render_frames(drawn, camera, r, colour, alpha, out.window_depth);
    if (passes.needs_surface()) {
        // The surface at each pixel's centre: a draw at 1x, unjittered (its colour is not used, nor
        // the shadow, which writes no pass).
        Framebuffer& fb = sized(target_, r.width, r.height);
        const DrawStats s = detail::render_scene_passes(renderer_, fb, objects, camera, r.settings, surface);
        if (!(colour || alpha || out.window_depth)) stats = s;
    }
    return stats;
}

DrawStats ViewRenderer::render(std::span<const ObjectView> objects, std::span<const Camera> cameras,
                               const ViewRequest& request, std::span<const PassImages> out) {
    check(request, cameras.size(), out);
    prepare(objects, request);
    DrawStats stats;
    for (std::size_t i = 0; i < cameras.size(); ++i) stats += render_view(objects, cameras[i], request, out[i]);
    return stats;
}

DrawStats ViewRenderer::render_each(std::span<const ObjectView> objects, std::span<const Camera> cameras,
                                    const ViewRequest& request, const PassImages& out,
                                    const std::function<bool(std::size_t)>& view_done) {
    check(request, 1, {&out, 1});
    prepare(objects, request);
    DrawStats stats;
    for (std::size_t i = 0; i < cameras.size(); ++i) {
        stats += render_view(objects, cameras[i], request, out);
        if (!view_done(i)) break;
    }
    return stats;
}

DrawStats ViewRenderer::render(const Scene& scene, std::span<const Camera> cameras, const ViewRequest& request,
                               std::span<const PassImages> out) {
    detail::require_aligned_arrays(scene);
    scene_views_.clear();
    for (const SceneObject& o : scene.objects) scene_views_.push_back(view_of(o));
    return render(scene_views_, cameras, request, out);
}

ViewImages make_view_images(const ViewRequest& request) {
    const std::size_t n = static_cast<std::size_t>(std::max(request.width, 0)) * static_cast<std::size_t>(std::max(request.height, 0));
    ViewImages v;
    v.width = request.width, v.height = request.height;
    const PassSet p = request.passes;
    if (p.has(Pass::colour)) v.colour.resize(n);
    if (p.has(Pass::alpha)) v.alpha.resize(n);
    if (p.has(Pass::depth)) v.depth.resize(n);
    if (p.has(Pass::range)) v.range.resize(n);
    if (p.has(Pass::normal)) v.normal.resize(n);
    if (p.has(Pass::instance)) v.instance.resize(n);
    if (p.has(Pass::material)) v.material.resize(n);
    if (p.has(Pass::primitive)) v.primitive.resize(n);
    if (p.has(Pass::uv)) v.uv.resize(n);
    return v;
}

std::vector<ViewImages> ViewRenderer::render(std::span<const ObjectView> objects, std::span<const Camera> cameras,
                                             const ViewRequest& request) {
    std::vector<ViewImages> images;
    std::vector<PassImages> out;
    for (std::size_t i = 0; i < cameras.size(); ++i) images.push_back(make_view_images(request));
    for (ViewImages& v : images) out.push_back(v.images());
    render(objects, cameras, request, out);
    return images;
}

std::vector<ViewImages> ViewRenderer::render(const Scene& scene, std::span<const Camera> cameras,
                                             const ViewRequest& request) {
    detail::require_aligned_arrays(scene);
    scene_views_.clear();
    for (const SceneObject& o : scene.objects) scene_views_.push_back(view_of(o));
    return render(std::span<const ObjectView>(scene_views_), cameras, request);
}

std::vector<ViewSpec> orbit_views(int n, float elevation, const ViewSpec& base) {
    std::vector<ViewSpec> views;
    for (int k = 0; k < n; ++k) views.push_back(looking_from(base, 2 * std::numbers::pi * k / n, elevation));
    return views;
}

std::vector<ViewSpec> sphere_views(int n, const ViewSpec& base) {
    const double golden_angle = std::numbers::pi * (3 - std::sqrt(5.0));
    std::vector<ViewSpec> views;
    for (int k = 0; k < n; ++k) {
        const double y = 1 - (2.0 * k + 1) / n;
        views.push_back(looking_from(base, std::fmod(golden_angle * k, 2 * std::numbers::pi), portable::asin(y)));
    }
    return views;
}

std::vector<ViewSpec> random_views(int n, std::uint64_t seed, const ViewSpec& base) {
    std::uint64_t state = seed;
    std::vector<ViewSpec> views;
    for (int k = 0; k < n; ++k) {
        const double y = 2 * unit_random(state) - 1;  // uniform height: uniform on the sphere
        const double azimuth = 2 * std::numbers::pi * unit_random(state);
        views.push_back(looking_from(base, azimuth, portable::asin(y)));
    }
    return views;
}

Result<std::vector<ViewSpec>> parse_rig(std::string_view spec, const ViewSpec& base) {
    std::vector<std::string_view> parts;
    for (std::size_t start = 0;;) {
        const std::size_t end = spec.find(':', start);
        parts.push_back(spec.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    const std::string text(spec);
    auto bad = [&](const std::string& why) {
        return Error{ErrorCode::invalid_argument, "bad view rig '" + text + "': " + why +
                                                      " (orbit:N[:ELEVATION], sphere:N, random:N:SEED or file:CAMERAS.json)"};
    };
    const std::string count_rule = "N must be a whole number from 1 to " + std::to_string(k_max_rig_views);
    const std::string_view kind = parts[0];
    if (kind != "orbit" && kind != "sphere" && kind != "random") return bad("unknown kind '" + std::string(kind) + "'");
    if (parts.size() < 2) return bad("the number of views N is missing");
    const std::optional<long long> n = parse_count(parts[1], k_max_rig_views);
    if (!n) return bad(count_rule + ", got '" + std::string(parts[1]) + "'");
    const int count = static_cast<int>(*n);
    if (kind == "orbit") {
        if (parts.size() > 3) return bad("too many fields");
        float elevation = base.elevation;
        if (parts.size() == 3) {
            const std::string e(parts[2]);
            char* end = nullptr;
            const float degrees = std::strtof(e.c_str(), &end);
            if (e.empty() || *end != '\0' || !std::isfinite(degrees) || degrees < -90 || degrees > 90)
                return bad("ELEVATION must be degrees from -90 to 90, got '" + e + "'");
            elevation = radians(degrees);
        }
        return orbit_views(count, elevation, base);
    }
    if (kind == "sphere") {
        if (parts.size() > 2) return bad("too many fields");
        return sphere_views(count, base);
    }
    if (parts.size() != 3) return bad(parts.size() < 3 ? "the SEED is missing" : "too many fields");
    const std::optional<long long> seed = parse_count(parts[2], 999'999'999'999'999'999);
    if (!seed && parts[2] != "0") return bad("SEED must be a whole number, got '" + std::string(parts[2]) + "'");
    return random_views(count, seed ? static_cast<std::uint64_t>(*seed) : 0, base);
}

}  // namespace facet
