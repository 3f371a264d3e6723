// facet command line: one view's render passes into files, in the formats --float-format picks
// (views_output.hpp lays out the folder). In: a view's images; out: its files and the
// transforms.json keys that name them. Formats:
//   color            8-bit PNG (RGB, or RGBA when some pixel is not opaque)
//   alpha            8-bit grayscale PNG, round(255 a)
//   instance, material, primitive
//                    16-bit grayscale PNG when every id of the scene fits (< 65536), else .npy uint32
//   depth, range, normal, uv
//                    npy: .npy float32, (H, W), (H, W, 3) or (H, W, 2)
//                    png: depth and range 16-bit, round(value / depth_scale), 0 for the background and
//                         for what does not fit; normal 8-bit RGB, round(255 (0.5 + 0.5 n)), (0, 0, 0)
//                         on the background; uv 16-bit RGB, round(65535 u), round(65535 v), 0 for
//                         u and v clamped to [0, 1]
//   exr (--float-format exr): every pass but color in one OpenEXR file per view (ZIP compression):
//                    FLOAT channels A, Z (depth), range, N.X, N.Y, N.Z, uv.U, uv.V; UINT channels
//                    instance, material, primitive.
// Every file is written atomically (a temporary file, renamed).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "facet/error.hpp"
#include "facet/views.hpp"
#include "options.hpp"

namespace facet::cli {

struct PassFileOptions {
    FloatFormat format = FloatFormat::npy;
    std::string folder;        // the files go into its pass folders (pass_folders)
    float depth_scale = 1.0f;  // png: model units per step of depth and range
    // The largest instance, material and primitive id of the scene: 16-bit PNG when it fits.
    std::uint32_t largest_id[3] = {0, 0, 0};
};

struct PassFiles {
    // transforms.json's key for each pass written ("file_path", "mask_path", "depth_file_path",
    // "<pass>_file_path") and its file, relative to the folder.
    std::vector<std::pair<std::string, std::string>> keys;
    std::vector<std::string> files;  // each file once
};

// The folders, relative to the output folder, that the files of `passes` go into: the passes'
// names ("color", "depth", ...), or "color" and "exr".
std::vector<std::string> pass_folders(PassSet passes, FloatFormat format);

// Writes the passes of one view, named `name` ("0000") in each pass folder. The error names the file.
Result<PassFiles> write_pass_files(const ViewImages& images, PassSet passes, const std::string& name,
                                   const PassFileOptions& options);

// Opens the OpenEXR writer's module now when `plan` writes EXR files: a worker does so before it
// confines itself, since the sandbox no longer lets it read the module (an error then is the
// writer's to report).
void load_writers_for(const RenderPlan& plan);

// A NumPy .npy file (format 1.0): `dtype` ("<f4", "<u4"), C order, `shape`, then the bytes of `data`.
Status write_npy(const std::string& path, const void* data, std::string_view dtype, const std::vector<int>& shape);

}  // namespace facet::cli
