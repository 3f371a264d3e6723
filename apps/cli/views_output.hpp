// facet command line: the views and render passes of one loaded scene into a folder (`facet render
// --views ... --passes ...`; `facet thumbs` for the objects of a manifest that ask for them). In: a
// Scene and a RenderPlan whose ViewsPlan says which views and passes; out, in the folder: one file
// per view and pass (color/0000.png, depth/0000.npy, ...), the exact cameras (cameras.json: OpenCV
// intrinsics and [R|t], camera-to-world in OpenGL's convention) and a transforms.json in the layout
// NeRF tools read (nerfstudio, instant-ngp). Everything is written into a staging folder beside the
// output and moved into place only when every file is written, so a failed run leaves nothing.
//
// The steps are split for the worker processes, which may create files only in folders that exist
// (the sandbox): the process that starts the worker stages the folders (stage_views), the worker
// renders and writes into them (render_views_into), and the first process moves them into place
// (commit_views) or removes them (discard_views).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "facet/camera.hpp"
#include "facet/error.hpp"
#include "facet/scene.hpp"
#include "options.hpp"

namespace facet::cli {

// A rig's views, and for a cameras file the image size its cameras are for (0 otherwise).
struct RigViews {
    std::vector<ViewSpec> views;
    int width = 0, height = 0;
};

// --views: orbit:N[:ELEVATION], sphere:N, random:N:SEED (facet/views.hpp's parse_rig, each view
// `base` with its angles), or file:CAMERAS.json (read_cameras_file). The error says what is wrong.
Result<RigViews> parse_views(const std::string& spec, const ViewSpec& base);

// Reads a cameras file: facet's cameras.json (what a run writes: "views", each with "K" or fx, fy,
// cx, cy (and skew), "R" and "t"), or a NeRF transforms.json ("frames", each with a 4x4
// "transform_matrix" camera-to-world in OpenGL's convention, and fl_x, fl_y, cx, cy, w, h at the
// top or per frame, pixel centres at +0.5). Each becomes an OpenCV camera, checked (validate).
// The error names the file and what in it is wrong.
Result<RigViews> read_cameras_file(const std::string& path);

// The folder a run writes into, and where it goes when done.
struct ViewsStaging {
    std::filesystem::path folder;  // "<output>.tmp<pid>", beside the output
    std::filesystem::path output;  // the folder asked for
    // The folders files are written into (the staging folder and its pass folders): the worker's
    // sandbox lets it create files in these.
    std::vector<std::string> write_folders;
};

// In the process that starts the job: a fresh staging folder beside `output` with the folders the
// plan's files go into. The error (a folder that cannot be made) names it.
Result<ViewsStaging> stage_views(const std::string& output, const ViewsPlan& plan);
// Moves the staging folder into place: it becomes `output` when that does not exist or is empty.
// Otherwise its files replace their namesakes in `output` and the other files there stay: the
// staging folder takes in hard links to them and is swapped with `output` in one rename
// (RENAME_EXCHANGE), so a killed run leaves `output` old or new, whole, and at worst the staging
// folder beside it. Where that cannot be done (`output` a symbolic link, a file system without the
// swap, a file that cannot be linked) each file is renamed into place, one at a time.
Status commit_views(const ViewsStaging& staging);
// Removes the staging folder and everything in it.
void discard_views(const ViewsStaging& staging);

struct ViewsReport {
    std::size_t views = 0;
    std::vector<std::string> files;  // written, relative to the folder
    DrawStats stats;
    double render_ms = 0, write_ms = 0;
};

// Renders every view of plan.views with its passes and writes the files, cameras.json and
// transforms.json into `folder` (a staging folder). `progress(done, total)` is called after each
// view, if given. The error names the file that could not be written.
Result<ViewsReport> render_views_into(const Scene& scene, const RenderPlan& plan, const std::string& folder,
                                      int threads, const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace facet::cli
