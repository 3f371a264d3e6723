// facet command line, the OpenEXR module (libfacet_exr.so; exr_module.hpp): one EXR file of FLOAT
// and UINT channels, ZIP compression. Not the temporary file and rename around it (pass_files.cpp).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include <cstdio>
#include <exception>

#include "exr_module.hpp"

extern "C" __attribute__((visibility("default"))) int facet_exr_write_v1(const char* path, int width, int height,
                                                                       const facet::cli::ExrChannel* channels, int count,
                                                                       char* error, std::size_t error_size) {
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (int i = 0; i < count; ++i) {
            const facet::cli::ExrChannel& c = channels[i];
            const Imf::PixelType type = c.is_uint ? Imf::UINT : Imf::FLOAT;
            header.channels().insert(c.name, Imf::Channel(type));
            frame.insert(c.name, Imf::Slice(type, const_cast<char*>(static_cast<const char*>(c.first)), c.pixel_bytes,
                                            c.pixel_bytes * static_cast<std::size_t>(width)));
        }
        Imf::OutputFile file(path, header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
        return 0;
    } catch (const std::exception& e) {
        std::snprintf(error, error_size, "%s", e.what());
    } catch (...) {
        std::snprintf(error, error_size, "unknown error");
    }
    return 1;
}
