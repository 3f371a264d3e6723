// facet io: point clouds (point_cloud.hpp): text formats read here, and the Scene any cloud becomes.
#include "io/point_cloud.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

// The whitespace-separated numbers of a line (at most `max`); false on something that is not one.
bool numbers_of(std::string_view line, std::vector<double>& out, std::size_t max = 16) {
    out.clear();
    std::size_t at = 0;
    while (at < line.size()) {
        while (at < line.size() && (line[at] == ' ' || line[at] == '\t' || line[at] == '\r' || line[at] == ',')) ++at;
        if (at == line.size()) break;
        double v = 0;
        const char* begin = line.data() + at;
        const char* start = begin + (*begin == '+' ? 1 : 0);
        const auto [end, ec] = std::from_chars(start, line.data() + line.size(), v);
        if (ec != std::errc() || out.size() == max) return false;
        out.push_back(v);
        at = static_cast<std::size_t>(end - line.data());
    }
    return true;
}

// Calls f(line, number) for each line of bytes (without its '\n'), numbered from 1, until f returns an error.
template <class F>
Status for_each_line(std::string_view bytes, F&& f) {
    std::size_t line_number = 0;
    for (std::size_t at = 0; at < bytes.size();) {
        std::size_t end = bytes.find('\n', at);
        if (end == std::string_view::npos) end = bytes.size();
        if (Status s = f(bytes.substr(at, end - at), ++line_number); !s) return s;
        at = end + 1;
    }
    return Ok{};
}

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

float unit(double v) { return std::isfinite(v) ? static_cast<float>(std::clamp(v, 0.0, 1.0)) : 1.0f; }

}  // namespace

Result<LoadedModel> point_cloud_model(const std::string& path, PointCloud cloud, const LoadOptions& options) {
    if (cloud.positions.size() > options.max_triangles)
        return fail(ErrorCode::limit_exceeded, path,
                    "has " + std::to_string(cloud.positions.size()) + " points, more than the limit of " +
                        std::to_string(options.max_triangles) + " (--max-triangles counts points too)");
    Mesh mesh;
    bool normals_ok = !cloud.normals.empty();
    for (const Vec3& n : cloud.normals) normals_ok = normals_ok && is_finite(n) && (n.x != 0 || n.y != 0 || n.z != 0);
    std::size_t dropped = 0;
    for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
        if (!is_finite(cloud.positions[i])) {
            ++dropped;
            continue;
        }
        mesh.points.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
        mesh.positions.push_back(cloud.positions[i]);
        if (normals_ok) mesh.normals.push_back(normalize(cloud.normals[i]));
        if (!cloud.colours.empty()) mesh.colours.push_back(cloud.colours[i]);
    }
    if (mesh.points.empty())
        return fail(ErrorCode::bad_format, path,
                    dropped ? "has no valid points (" + std::to_string(dropped) + " with non-finite coordinates)"
                            : std::string("contains no points"));
    LoadedModel out;
    if (dropped) out.warnings.push_back(path + ": dropped " + std::to_string(dropped) + " points with non-finite coordinates");
    SceneObject object;
    object.mesh = std::move(mesh);
    object.model = up_axis_root(options.up_axis) * Mat4::identity();
    out.scene.objects.push_back(std::move(object));
    return out;
}

Result<LoadedModel> read_text_points(const std::string& path, std::string_view bytes, bool pts, const LoadOptions& options) {
    PointCloud cloud;
    std::vector<double> v;
    std::size_t columns = 0;
    bool first = true;
    const Status read = for_each_line(bytes, [&](std::string_view raw, std::size_t number) -> Status {
        const std::string_view line = trimmed(raw);
        if (line.empty() || line[0] == '#' || line.substr(0, 2) == "//") return Ok{};
        if (!numbers_of(line, v))
            return fail(ErrorCode::bad_format, path, "line " + std::to_string(number) + " is not a line of numbers: '" +
                                                         readable(std::string(line), 60) + "'");
        if (first && pts && v.size() == 1) {  // PTS: the count
            first = false;
            return Ok{};
        }
        first = false;
        if (columns == 0) {
            columns = v.size();
            const bool known = pts ? columns == 3 || columns == 4 || columns == 7 : columns == 3 || columns == 6;
            if (!known)
                return fail(ErrorCode::bad_format, path,
                            "line " + std::to_string(number) + " has " + std::to_string(columns) + " numbers; " +
                                (pts ? "PTS lines are x y z [intensity [r g b]]" : "XYZ lines are x y z [nx ny nz]"));
        } else if (v.size() != columns) {
            return fail(ErrorCode::bad_format, path,
                        "line " + std::to_string(number) + " has " + std::to_string(v.size()) + " numbers, the first point's line " +
                            std::to_string(columns));
        }
        if (cloud.positions.size() >= options.max_triangles)
            return fail(ErrorCode::limit_exceeded, path,
                        "has more than " + std::to_string(options.max_triangles) + " points (--max-triangles counts points too)");
        cloud.positions.push_back({static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])});
        if (!pts && columns == 6) cloud.normals.push_back({static_cast<float>(v[3]), static_cast<float>(v[4]), static_cast<float>(v[5])});
        if (pts && columns == 7) cloud.colours.push_back({unit(v[4] / 255), unit(v[5] / 255), unit(v[6] / 255), 1.0f});
        return Ok{};
    });
    if (!read) return read.error();
    return point_cloud_model(path, std::move(cloud), options);
}

std::optional<Result<LoadedModel>> read_obj_points(const std::string& path, std::string_view bytes, const LoadOptions& options) {
    PointCloud cloud;
    std::vector<double> v;
    bool colours = false, has_elements = false;
    // The whole file is scanned for faces, lines and points first: a file that has any is not a
    // cloud, and its error is assimp's, whatever its vertices look like.
    (void)for_each_line(bytes, [&](std::string_view raw, std::size_t) -> Status {
        const std::string_view line = trimmed(raw);
        if (line.size() >= 2 && (line[1] == ' ' || line[1] == '\t') && (line[0] == 'f' || line[0] == 'l' || line[0] == 'p'))
            has_elements = true;
        return Ok{};
    });
    if (has_elements) return std::nullopt;
    const Status read = for_each_line(bytes, [&](std::string_view raw, std::size_t number) -> Status {
        const std::string_view line = trimmed(raw);
        if (line.size() < 2 || (line[1] != ' ' && line[1] != '\t')) return Ok{};
        if (line[0] != 'v') return Ok{};
        if (!numbers_of(line.substr(2), v) || (v.size() != 3 && v.size() != 4 && v.size() != 6 && v.size() != 7))
            return fail(ErrorCode::bad_format, path, "line " + std::to_string(number) + " is not a vertex: '" +
                                                         readable(std::string(line), 60) + "'");
        if (cloud.positions.size() >= options.max_triangles)
            return fail(ErrorCode::limit_exceeded, path,
                        "has more than " + std::to_string(options.max_triangles) + " points (--max-triangles counts points too)");
        if (cloud.positions.empty()) colours = v.size() >= 6;
        cloud.positions.push_back({static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])});
        if (colours) {
            if (v.size() < 6) return fail(ErrorCode::bad_format, path, "line " + std::to_string(number) + " has no colour, the first vertex has one");
            const std::size_t c = v.size() - 3;  // "x y z [w] r g b": the colour is the last three
            cloud.colours.push_back({unit(v[c]), unit(v[c + 1]), unit(v[c + 2]), 1.0f});
        }
        return Ok{};
    });
    if (cloud.positions.empty()) return std::nullopt;
    if (!read) return read.error();
    return point_cloud_model(path, std::move(cloud), options);
}

}  // namespace facet::io_detail
