// facet io, the fast path: OFF, STL and PLY files read by facet's own readers (plain_off.hpp,
// stl.hpp, ply.hpp) into exactly the Scene the assimp path makes of them, without assimp. In: the
// file's first bytes and size, whose header is parsed once for the pre-check and for the reader;
// then the whole file. Out: the pre-check's verdict, then a LoadedModel, or nullopt for a file the
// readers decline (or a limit the Scene would pass), which the assimp path then reads and reports.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "exec/fresh_pages.hpp"
#include "facet/model.hpp"
#include "io/plain_off.hpp"
#include "io/ply.hpp"
#include "io/stl.hpp"

namespace facet::io_detail {

// OBJ files (and their MTL files) and glTF 2.0 files (.gltf, .glb) read by facet's own readers
// (obj.hpp, gltf.hpp) into the scene assimp's importers make of them, converted as the assimp path converts it (assimp_scene.hpp); nullopt for
// the files the reader declines, which the assimp path then reads. `ext` is the extension in lower
// case, `size` the file's.
std::optional<Result<LoadedModel>> load_own_scene(const std::string& path, const std::string& ext, std::uint64_t size,
                                                  const LoadOptions& options);

// A file's bytes, followed by a NUL (the text readers stop at it, as at std::string's), in memory
// that is not cleared first: the read writes every byte, and clearing a large file's buffer before
// it cost as much as the read (2.6 MB for the bunny). Files of 32 MiB and more (which glibc maps
// fresh anyway, past its largest mmap threshold) go into fresh pages of 2 MiB
// (exec/fresh_pages.hpp): the 1M-triangle OBJ's 38 MB faulted in 19 times, not 9,200; smaller ones
// take the heap's memory, which a worker reuses from file to file, advised for 2 MiB pages too.
class FileBytes {
public:
    // The file's pages themselves, mapped read-only (map_whole_file).
    struct Mapped {};

    explicit FileBytes(std::size_t size) : size_(size) {
        if (size >= k_fresh_from) {
            fresh_ = detail::ZeroedArray<char>(size + 1);  // the NUL: zero already
            data_ = fresh_.data();
        } else {
            bytes_ = std::make_unique_for_overwrite<char[]>(size + 1);
            data_ = bytes_.get();
            detail::advise_huge_pages(data_, size + 1);  // a fresh process's read faults in 2 MiB at a time
            data_[size] = '\0';
        }
    }
    FileBytes(Mapped, char* start, std::size_t mapped, std::size_t size) : mapping_(start, mapped), data_(start), size_(size) {}
    char* data() { return data_; }  // not for a mapped file's bytes (read-only)
    const char* data() const { return data_; }
    std::size_t size() const { return size_; }
    std::string_view view() const { return {data_, size_}; }
    operator std::string_view() const { return view(); }

    static constexpr std::size_t k_fresh_from = std::size_t{32} << 20;

private:
    // An address range unmapped with the bytes (empty: none).
    class Mapping {
    public:
        Mapping() = default;
        Mapping(char* start, std::size_t bytes) : start_(start), bytes_(bytes) {}
        Mapping(Mapping&& o) noexcept : start_(std::exchange(o.start_, nullptr)), bytes_(std::exchange(o.bytes_, 0)) {}
        Mapping& operator=(Mapping&& o) noexcept {
            std::swap(start_, o.start_);
            std::swap(bytes_, o.bytes_);
            return *this;
        }
        ~Mapping() {
            if (start_) munmap(start_, bytes_);
        }

    private:
        char* start_ = nullptr;
        std::size_t bytes_ = 0;
    };
    std::unique_ptr<char[]> bytes_;
    detail::ZeroedArray<char> fresh_;
    Mapping mapping_;
    char* data_ = nullptr;
    std::size_t size_;
};

// The file's `size` bytes, or nullopt when it cannot be read whole or has changed size.
std::optional<FileBytes> read_whole_file(const std::string& path, std::uint64_t size);

// The same bytes as read_whole_file's, but the file's own pages in the page cache, mapped read-only
// (MAP_POPULATE: faulted in at once) with a zero byte after them: no copy and no fresh memory for
// the text (the 1M-triangle OBJ's 38 MB). A file cut short while it is mapped ends the process with
// SIGBUS where its bytes are read, so only for LoadOptions::map_files (processes whose end is
// reported: facet's worker, load_model_isolated's child). read_whole_file's result where the
// mapping fails; nullopt when the file has changed size.
std::optional<FileBytes> map_whole_file(const std::string& path, std::uint64_t size);

// The bytes every whole-file reader takes (OBJ, glTF, OFF, STL, PLY, XYZ/PTS): map_whole_file's
// where `options.map_files` and the file has FileBytes::k_fresh_from bytes or more, read_whole_file's
// otherwise.
std::optional<FileBytes> whole_file(const std::string& path, std::uint64_t size, const LoadOptions& options);

class OwnFormatHeader {
public:
    // The header of a file with the extension `ext` (lower case) whose format has a reader of
    // facet's own; nullopt for the other formats. `head` is the file's first bytes, followed by a
    // NUL character (as std::string's data is); `size` the file's.
    static std::optional<OwnFormatHeader> parse(const std::string& ext, std::string_view head, std::uint64_t size);

    // The pre-check, for the assimp path too: refuses headers that claim more than the file holds
    // or than the options allow, and the ones assimp 5.2.5 cannot read safely.
    Status check(const std::string& path, std::uint64_t size, const LoadOptions& options) const;

    // Reads the whole file (which must still start with `head`) with facet's own reader.
    std::optional<LoadedModel> load(const std::string& path, std::string_view head, std::uint64_t size,
                                    const LoadOptions& options) const;

    // A PLY point cloud (ply.hpp, is_ply_point_cloud) read whole, or its error; nullopt for any
    // other file. Not a fast path: assimp reads no such file.
    std::optional<Result<LoadedModel>> load_point_cloud(const std::string& path, std::string_view head,
                                                        std::uint64_t size, const LoadOptions& options) const;

private:
    explicit OwnFormatHeader(std::variant<OffHeader, StlHeader, PlyHeader> header) : header_(std::move(header)) {}
    std::variant<OffHeader, StlHeader, PlyHeader> header_;
};

}  // namespace facet::io_detail
