// facet command line: views and render passes into a folder (views_output.hpp): the rig, staging
// and committing the folder, the render loop over the views, and the cameras files. The pass
// images' file formats are pass_files.cpp's.
#include "views_output.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "../../src/math/portable_trig.hpp"  // header-only; not in the public headers, hence the path
#include "facet/io.hpp"
#include "json.hpp"
#include "pass_files.hpp"

namespace facet::cli {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

Error bad_file(const std::string& path, const std::string& what) {
    return Error{ErrorCode::bad_format, path + ": " + what};
}

// A cameras file is a few numbers per view: anything larger than this is not one.
constexpr std::uintmax_t k_max_cameras_file_bytes = 64u << 20;

Result<std::string> read_text(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return Error{ErrorCode::io, path + ": no such cameras file"};
    if (fs::file_size(path, ec) > k_max_cameras_file_bytes)
        return bad_file(path, "larger than a cameras file can be (64 MiB)");
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) return Error{ErrorCode::io, path + ": cannot be read"};
    return text.str();
}

// Readers of the JSON tree that name what is wrong.
struct Reader {
    const std::string& path;
    std::string where;  // "frame 3", ...

    Error bad(const std::string& what) const { return bad_file(path, (where.empty() ? "" : where + ": ") + what); }

    Result<double> number(const json::Value& obj, const char* key) const {
        const json::Value* v = obj.find(key);
        if (!v) return bad(std::string("\"") + key + "\" is missing");
        if (!v->is(json::Value::Type::number)) return bad(std::string("\"") + key + "\" must be a number, not " + json::type_name(v->type));
        return v->number;
    }
    // The number at `key` of `obj`, else of `outer` (per-frame values override the top level's).
    Result<double> number(const json::Value& obj, const json::Value& outer, const char* key) const {
        return obj.find(key) ? number(obj, key) : number(outer, key);
    }
    // A rows x cols matrix as nested arrays (or `rows` numbers when cols is 0).
    Status matrix(const json::Value& obj, const char* key, int rows, int cols, double* out) const {
        const json::Value* v = obj.find(key);
        if (!v) return bad(std::string("\"") + key + "\" is missing");
        const std::string shape = cols ? std::to_string(rows) + "x" + std::to_string(cols) + " matrix (rows of numbers)"
                                       : std::to_string(rows) + " numbers";
        if (!v->is(json::Value::Type::array) || v->items.size() != static_cast<std::size_t>(rows))
            return bad(std::string("\"") + key + "\" must be a " + shape);
        for (int r = 0; r < rows; ++r) {
            const json::Value& row = v->items[static_cast<std::size_t>(r)];
            if (cols == 0) {
                if (!row.is(json::Value::Type::number)) return bad(std::string("\"") + key + "\" must be " + shape);
                out[r] = row.number;
                continue;
            }
            if (!row.is(json::Value::Type::array) || row.items.size() != static_cast<std::size_t>(cols))
                return bad(std::string("\"") + key + "\" must be a " + shape);
            for (int c = 0; c < cols; ++c) {
                const json::Value& x = row.items[static_cast<std::size_t>(c)];
                if (!x.is(json::Value::Type::number)) return bad(std::string("\"") + key + "\" must be a " + shape);
                out[r * cols + c] = x.number;
            }
        }
        return Ok{};
    }
    Result<int> size(const json::Value& obj, const json::Value& outer, const char* key) const {
        Result<double> v = number(obj, outer, key);
        if (!v) return v.error();
        if (!(*v >= 1 && *v <= k_max_target_size && *v == std::floor(*v)))
            return bad(std::string("\"") + key + "\" must be a whole number of pixels from 1 to " + std::to_string(k_max_target_size));
        return static_cast<int>(*v);
    }
};

// A facet cameras.json view: K (or fx, fy, cx, cy, skew), R, t; width and height here or at the top.
Result<OpenCvCamera> facet_view(const Reader& r, const json::Value& view, const json::Value& top) {
    OpenCvCamera c;
    Result<int> w = r.size(view, top, "width"), h = r.size(view, top, "height");
    if (!w) return w.error();
    if (!h) return h.error();
    c.width = *w, c.height = *h;
    if (view.find("K")) {
        double k[9];
        if (Status s = r.matrix(view, "K", 3, 3, k); !s) return s.error();
        if (k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1) return r.bad("\"K\" must be [[fx, skew, cx], [0, fy, cy], [0, 0, 1]]");
        c.fx = k[0], c.skew = k[1], c.cx = k[2], c.fy = k[4], c.cy = k[5];
    } else {
        for (auto [key, to] : {std::pair{"fx", &c.fx}, {"fy", &c.fy}, {"cx", &c.cx}, {"cy", &c.cy}}) {
            Result<double> v = r.number(view, key);
            if (!v) return v.error();
            *to = *v;
        }
        if (view.find("skew")) {
            Result<double> v = r.number(view, "skew");
            if (!v) return v.error();
            c.skew = *v;
        }
    }
    if (Status s = r.matrix(view, "R", 3, 3, c.rotation.data()); !s) return s.error();
    if (Status s = r.matrix(view, "t", 3, 0, c.translation.data()); !s) return s.error();
    return c;
}

// A NeRF frame: transform_matrix (camera-to-world, OpenGL axes: x right, y up, looking down -z),
// intrinsics with pixel centres at +0.5 (fl_x, fl_y, cx, cy, w, h, or camera_angle_x), each in the
// frame or at the top.
Result<OpenCvCamera> nerf_frame(const Reader& r, const json::Value& frame, const json::Value& top) {
    OpenCvCamera c;
    Result<int> w = r.size(frame, top, "w"), h = r.size(frame, top, "h");
    if (!w) return w.error();
    if (!h) return h.error();
    c.width = *w, c.height = *h;
    const bool has_fl = frame.find("fl_x") || top.find("fl_x");
    if (has_fl) {
        Result<double> fx = r.number(frame, top, "fl_x");
        if (!fx) return fx.error();
        c.fx = *fx;
    } else {
        Result<double> angle = r.number(frame, top, "camera_angle_x");  // instant-ngp's and Blender's NeRF sets
        if (!angle) return r.bad("\"fl_x\" (or \"camera_angle_x\") is missing");
        // The portable tangent: glibc's picks an FMA variant by CPU, and fx is written to the
        // folder's cameras files and makes the projection, so it must have the same bits everywhere.
        c.fx = 0.5 * c.width / portable::tan(*angle / 2);
    }
    c.fy = c.fx;
    if (frame.find("fl_y") || top.find("fl_y")) {
        Result<double> fy = r.number(frame, top, "fl_y");
        if (!fy) return fy.error();
        c.fy = *fy;
    }
    c.cx = c.width / 2.0, c.cy = c.height / 2.0;
    if (frame.find("cx") || top.find("cx")) {
        Result<double> v = r.number(frame, top, "cx");
        if (!v) return v.error();
        c.cx = *v;
    }
    if (frame.find("cy") || top.find("cy")) {
        Result<double> v = r.number(frame, top, "cy");
        if (!v) return v.error();
        c.cy = *v;
    }
    c.cx -= 0.5, c.cy -= 0.5;  // to OpenCV's pixel centres
    double m[16];
    if (Status s = r.matrix(frame, "transform_matrix", 4, 4, m); !s) return s.error();
    if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1) return r.bad("\"transform_matrix\" must end with the row [0, 0, 0, 1]");
    set_camera_to_world_gl(c, std::to_array(m));
    return c;
}

std::string view_name(std::size_t i) {
    char name[24];
    std::snprintf(name, sizeof(name), "%04zu", i);
    return name;
}

// A number exactly as a double, for cameras that must come back bit for bit.
std::string exact(double v) {
    char s[32];
    std::snprintf(s, sizeof(s), "%.17g", v);
    return s;
}

std::string rows(const double* m, int rows, int cols) {
    std::string s = "[";
    for (int r = 0; r < rows; ++r) {
        s += r ? ", [" : "[";
        for (int c = 0; c < cols; ++c) s += (c ? ", " : "") + exact(m[r * cols + c]);
        s += "]";
    }
    return s + "]";
}

// What a run wrote for each view.
struct WrittenView {
    OpenCvCamera camera;
    float near, far;
    PassFiles files;
};

const char* const k_cameras_convention =
    "OpenCV: x right, y down, z forward; a world point p is at R p + t in camera space and at pixel "
    "u = fx x/z + skew y/z + cx, v = fy y/z + cy, where pixel (i, j) has its centre at (u, v) = (i, j) (facet's and "
    "OpenGL's pixel centres are at +0.5). camera_to_world_gl: the camera's pose with OpenGL's axes (x right, y up, "
    "looking down -z). Depth: distance along the camera's z axis, range: along the pixel's ray, in model units.";

std::string cameras_json(const std::vector<WrittenView>& views, int width, int height) {
    std::string s = "{\n  \"convention\": " + json::quote(k_cameras_convention) + ",\n";
    s += "  \"width\": " + std::to_string(width) + ",\n  \"height\": " + std::to_string(height) + ",\n  \"views\": [\n";
    for (std::size_t i = 0; i < views.size(); ++i) {
        const OpenCvCamera& c = views[i].camera;
        const double k[9] = {c.fx, c.skew, c.cx, 0, c.fy, c.cy, 0, 0, 1};
        s += "    {\"name\": \"" + view_name(i) + "\", \"width\": " + std::to_string(c.width) +
             ", \"height\": " + std::to_string(c.height) + ", \"fx\": " + exact(c.fx) + ", \"fy\": " + exact(c.fy) +
             ", \"cx\": " + exact(c.cx) + ", \"cy\": " + exact(c.cy) + ", \"skew\": " + exact(c.skew) +
             ",\n     \"K\": " + rows(k, 3, 3) + ",\n     \"R\": " + rows(c.rotation.data(), 3, 3) +
             ",\n     \"t\": [" + exact(c.translation[0]) + ", " + exact(c.translation[1]) + ", " + exact(c.translation[2]) +
             "],\n     \"camera_to_world_gl\": " + rows(camera_to_world_gl(c).data(), 4, 4) +
             ",\n     \"near\": " + exact(views[i].near) + ", \"far\": " + exact(views[i].far) + "}" +
             (i + 1 < views.size() ? ",\n" : "\n");
    }
    return s + "  ]\n}\n";
}

// nerfstudio's and instant-ngp's layout: intrinsics at the top when every view shares them (per
// frame otherwise), pixel centres at +0.5; per frame its camera-to-world and one key per pass.
std::string transforms_json(const std::vector<WrittenView>& views, double depth_unit) {
    auto intrinsics = [](const OpenCvCamera& c, const std::string& indent) {
        return indent + "\"fl_x\": " + exact(c.fx) + ", \"fl_y\": " + exact(c.fy) + ", \"cx\": " + exact(c.cx + 0.5) +
               ", \"cy\": " + exact(c.cy + 0.5) + ", \"w\": " + std::to_string(c.width) + ", \"h\": " + std::to_string(c.height);
    };
    bool shared = true;
    for (const WrittenView& v : views) {
        const OpenCvCamera &a = v.camera, &b = views.front().camera;
        shared &= a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.width == b.width && a.height == b.height;
    }
    std::string s = "{\n  \"camera_model\": \"OPENCV\", \"k1\": 0, \"k2\": 0, \"p1\": 0, \"p2\": 0,\n";
    if (shared) s += intrinsics(views.front().camera, "  ") + ",\n";
    s += "  \"depth_unit_scale_factor\": " + exact(depth_unit) + ",\n  \"frames\": [\n";
    for (std::size_t i = 0; i < views.size(); ++i) {
        const WrittenView& v = views[i];
        s += "    {";
        bool first = true;
        for (const auto& [key, file] : v.files.keys) {
            s += (first ? "" : ", ") + json::quote(key) + ": " + json::quote(file);
            first = false;
        }
        if (!shared) s += (first ? "" : ",\n") + intrinsics(v.camera, "     "), first = false;
        s += std::string(first ? "" : ",\n     ") + "\"transform_matrix\": " + rows(camera_to_world_gl(v.camera).data(), 4, 4) + "}";
        s += i + 1 < views.size() ? ",\n" : "\n";
    }
    return s + "  ]\n}\n";
}

}  // namespace

Result<RigViews> read_cameras_file(const std::string& path) {
    Result<std::string> text = read_text(path);
    if (!text) return text.error();
    Result<json::Value> root = json::parse(*text);
    if (!root) return bad_file(path, "not JSON: " + root.error().message);
    if (!root->is(json::Value::Type::object)) return bad_file(path, "a cameras file is a JSON object");
    const json::Value* views = root->find("views");
    const json::Value* frames = root->find("frames");
    const json::Value* list = views ? views : frames;
    if (!list || !list->is(json::Value::Type::array))
        return bad_file(path, "neither \"views\" (facet's cameras.json) nor \"frames\" (a NeRF transforms.json) is a list of cameras");
    if (list->items.empty()) return bad_file(path, "it lists no camera");
    if (list->items.size() > static_cast<std::size_t>(k_max_rig_views))
        return bad_file(path, "more than " + std::to_string(k_max_rig_views) + " cameras");
    RigViews out;
    for (std::size_t i = 0; i < list->items.size(); ++i) {
        const Reader r{path, (views ? "view " : "frame ") + std::to_string(i)};
        const json::Value& item = list->items[i];
        if (!item.is(json::Value::Type::object)) return r.bad("a camera is a JSON object");
        Result<OpenCvCamera> c = views ? facet_view(r, item, *root) : nerf_frame(r, item, *root);
        if (!c) return c.error();
        if (Status s = validate(*c); !s) return r.bad(s.error().message);
        ViewSpec v;
        v.opencv = *c;
        out.views.push_back(v);
        if (i == 0) out.width = c->width, out.height = c->height;
    }
    return out;
}

Result<RigViews> parse_views(const std::string& spec, const ViewSpec& base) {
    if (spec.rfind("file:", 0) == 0) {
        if (spec.size() == 5) return Error{ErrorCode::invalid_argument, "file: needs the cameras file's path (file:CAMERAS.json)"};
        Result<RigViews> file = read_cameras_file(spec.substr(5));
        if (!file) return file.error();
        for (ViewSpec& v : file->views) v.near = base.near, v.far = base.far;
        return file;
    }
    Result<std::vector<ViewSpec>> rig = parse_rig(spec, base);
    if (!rig) return rig.error();
    return RigViews{std::move(*rig), 0, 0};
}

Result<ViewsStaging> stage_views(const std::string& output, const ViewsPlan& plan) {
    std::error_code ec;
    fs::path out = fs::absolute(output, ec).lexically_normal();
    if (!out.has_filename()) out = out.parent_path();  // "dir/" names "dir"
    if (ec || !out.has_filename() || out.filename() == "." || out.filename() == "..")
        return Error{ErrorCode::io, output + ": not a folder name the views can be written to"};
    if (fs::exists(out, ec) && !fs::is_directory(out, ec)) return Error{ErrorCode::io, output + ": exists and is not a folder"};
    ViewsStaging s;
    s.output = out;
    s.folder = out.parent_path() / (out.filename().string() + ".tmp" + std::to_string(::getpid()));
    fs::create_directories(out.parent_path(), ec);
    if (ec) return Error{ErrorCode::io, out.parent_path().string() + ": cannot create the folder: " + ec.message()};
    fs::remove_all(s.folder, ec);  // one a killed run with this pid left
    std::vector<std::string> folders{""};
    for (const std::string& f : pass_folders(plan.passes, plan.float_format)) folders.push_back(f);
    for (const std::string& f : folders) {
        const fs::path p = f.empty() ? s.folder : s.folder / f;
        if (!fs::create_directory(p, ec) || ec) {
            // The reason before the clean-up's own error code replaces it (it said "exists" for any).
            const std::string why = ec ? ec.message() : std::string("exists");
            fs::remove_all(s.folder, ec);
            return Error{ErrorCode::io, output + ": cannot create files beside it (" + p.string() + ": " + why + ")"};
        }
        s.write_folders.push_back(p.string());
    }
    return s;
}

namespace {

// Links into `to` what `from` holds that `to` does not (hard links for files, the same symbolic
// links, folders made alike and filled the same way), so that `to` can replace `from` whole: the
// files of `to` win over their namesakes. False when something cannot be carried (a special file,
// a file on another device, links refused): `carried` then lists what was.
bool carry_over(const fs::path& from, const fs::path& to, std::vector<fs::path>& carried) {
    std::error_code ec;
    for (fs::directory_iterator it(from, ec), end; !ec && it != end; it.increment(ec)) {
        const fs::path target = to / it->path().filename();
        const fs::file_status own = it->symlink_status(ec);
        if (ec) return false;
        const fs::file_status there = fs::symlink_status(target, ec);
        if (fs::exists(there)) {
            if (fs::is_directory(there) && fs::is_directory(own) && !carry_over(it->path(), target, carried)) return false;
            continue;  // the new file replaces it
        }
        if (fs::is_symlink(own)) fs::copy_symlink(it->path(), target, ec);
        else if (fs::is_directory(own)) {
            fs::create_directory(target, it->path(), ec);
            if (!ec) carried.push_back(target);
            if (!ec && !carry_over(it->path(), target, carried)) return false;
            continue;
        } else if (fs::is_regular_file(own)) fs::create_hard_link(it->path(), target, ec);
        else return false;
        if (ec) return false;
        carried.push_back(target);
    }
    return !ec;
}

}  // namespace

Status commit_views(const ViewsStaging& s) {
    std::error_code ec;
    const fs::file_status out = fs::symlink_status(s.output, ec);
    if (!fs::exists(out) || (fs::is_directory(out) && fs::is_empty(s.output, ec))) {
        fs::rename(s.folder, s.output, ec);  // replaces an empty folder
        if (!ec) return Ok{};
    }
    // Into an existing folder: the staging folder takes in the folder's other files (links, no
    // copies), then the two are swapped in one step (renameat2's RENAME_EXCHANGE), so that the
    // folder is at every moment either the old one or the new one whole; the old one is removed.
    std::vector<fs::path> carried;
    if (fs::is_directory(out) && carry_over(s.output, s.folder, carried)) {
        fs::permissions(s.folder, fs::status(s.output, ec).permissions(), ec);
        if (::renameat2(AT_FDCWD, s.folder.c_str(), AT_FDCWD, s.output.c_str(), RENAME_EXCHANGE) == 0) {
            discard_views(s);  // the old folder, now under the staging name
            return Ok{};
        }
    }
    // Where the swap cannot be made (a symbolic link to a folder, a file system without it, a file
    // that cannot be linked): each new file replaces its namesake, one rename each.
    std::sort(carried.begin(), carried.end());
    std::vector<fs::path> files;
    for (fs::recursive_directory_iterator it(s.folder, ec), end; !ec && it != end; it.increment(ec))
        if (it->is_regular_file() && !std::binary_search(carried.begin(), carried.end(), it->path())) files.push_back(it->path());
    for (const fs::path& f : files) {
        const fs::path to = s.output / f.lexically_relative(s.folder);
        fs::create_directories(to.parent_path(), ec);
        if (!ec) fs::rename(f, to, ec);
        if (ec) {
            discard_views(s);
            return Error{ErrorCode::io, to.string() + ": cannot be written: " + ec.message()};
        }
    }
    discard_views(s);
    return Ok{};
}

void discard_views(const ViewsStaging& s) {
    std::error_code ec;
    fs::remove_all(s.folder, ec);
}

Result<ViewsReport> render_views_into(const Scene& scene, const RenderPlan& plan, const std::string& folder, int threads,
                                      const std::function<void(std::size_t, std::size_t)>& progress) {
    const ViewsPlan& vp = *plan.views;
    std::vector<ObjectView> objects;
    for (const SceneObject& o : scene.objects) objects.push_back(view_of(o));
    const float aspect = static_cast<float>(plan.width) / static_cast<float>(plan.height);

    // The cameras, each made exact: converted to OpenCV's form and rendered from that, so that the
    // numbers written are the camera rendered, and reading them back renders the same bytes.
    std::vector<Camera> framed;
    if (!vp.views.empty()) framed = make_cameras(objects, vp.views, aspect);
    else if (plan.use_default_scene_camera) framed.push_back(default_scene_camera(aspect));
    else framed.push_back(make_camera(objects, plan.view, aspect));
    std::vector<ViewSpec> exact_views;
    for (const Camera& c : framed) {
        ViewSpec v;
        std::optional<OpenCvCamera> cv = to_opencv(c, plan.width, plan.height);
        if (!cv) return Error{ErrorCode::invalid_argument, "views need right-handed perspective cameras"};
        orthonormalize(*cv);  // so that transforms.json's camera-to-world reads back as this camera
        v.opencv = cv;
        v.near = plan.view.near, v.far = plan.view.far;
        exact_views.push_back(v);
    }
    const std::vector<Camera> cameras = make_cameras(objects, exact_views, aspect);

    ViewRequest request = view_request(plan);
    request.passes = vp.passes;
    request.normal_space = vp.normal_space;
    PassFileOptions files;
    files.format = vp.float_format;
    files.folder = folder;
    float far = 0;
    for (const Camera& c : cameras) far = std::max(far, c.far);
    files.depth_scale = vp.depth_scale.value_or(far / 65535.0f);
    std::vector<std::uint32_t> materials;
    std::vector<const Material*> scratch;
    material_ids(objects, materials, scratch);
    files.largest_id[0] = static_cast<std::uint32_t>(objects.size());
    files.largest_id[1] = materials.empty() ? 0 : *std::max_element(materials.begin(), materials.end());
    for (const ObjectView& o : objects)
        files.largest_id[2] = std::max(files.largest_id[2], static_cast<std::uint32_t>(o.indices.size() / 3));

    ViewRenderer renderer({.threads = threads});
    ViewImages images = make_view_images(request);
    const PassImages out[] = {images.images()};
    ViewsReport report;
    std::vector<WrittenView> written;
    std::optional<Error> failed;
    Clock::time_point start = Clock::now();
    // Each view written as soon as it is rendered, into the one set of images.
    report.stats = renderer.render_each(objects, cameras, request, out[0], [&](std::size_t i) {
        report.render_ms += ms_since(start);
        start = Clock::now();
        Result<PassFiles> f = write_pass_files(images, request.passes, view_name(i), files);
        if (!f) {
            failed = f.error();
            return false;
        }
        report.write_ms += ms_since(start);
        report.files.insert(report.files.end(), f->files.begin(), f->files.end());
        written.push_back({*to_opencv(cameras[i], plan.width, plan.height), cameras[i].near, cameras[i].far, std::move(*f)});
        if (progress) progress(i + 1, cameras.size());
        start = Clock::now();
        return true;
    });
    if (failed) return *failed;
    const std::string cameras_text = cameras_json(written, plan.width, plan.height);
    const double depth_unit = vp.float_format == FloatFormat::png ? files.depth_scale : 1.0;
    const std::string transforms_text = transforms_json(written, depth_unit);
    for (const auto& [name, text] : {std::pair{"cameras.json", &cameras_text}, {"transforms.json", &transforms_text}}) {
        if (Status s = write_file_atomic((fs::path(folder) / name).string(), text->data(), text->size()); !s) return s.error();
        report.files.push_back(name);
    }
    report.views = cameras.size();
    return report;
}

}  // namespace facet::cli
