// facet image: the render target (RGBA8 colour + float depth) and error names.
#include <algorithm>
#include <string>

#include "facet/error.hpp"
#include "facet/image.hpp"

namespace facet {

const char* to_string(ErrorCode code) {
    switch (code) {
        case ErrorCode::invalid_argument: return "invalid argument";
        case ErrorCode::io: return "i/o error";
        case ErrorCode::bad_format: return "bad format";
        case ErrorCode::unsupported: return "unsupported";
        case ErrorCode::limit_exceeded: return "limit exceeded";
    }
    return "error";
}

namespace {

void check_size(int width, int height) {
    if (width < 1 || height < 1 || width > k_max_target_size || height > k_max_target_size)
        throw FacetError(Error{ErrorCode::invalid_argument,
                               "Framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                                   " is outside 1.." + std::to_string(k_max_target_size)});
}

}  // namespace

Framebuffer::Framebuffer(int width, int height) : width_(width), height_(height) {
    check_size(width, height);
    colour_.resize(pixel_count());
    depth_.assign(pixel_count(), 1.0f);
}

Framebuffer::Framebuffer(int width, int height, Rgba8* colour) : width_(width), height_(height), external_colour_(colour) {
    check_size(width, height);
    if (!colour) colour_.resize(pixel_count());
    depth_.resize(pixel_count());  // left as the memory holds it: the first draw's clear writes it
}

void Framebuffer::clear(Vec4 colour, float depth) {
    clear_colour(colour);
    clear_depth(depth);
}

void Framebuffer::clear_colour(Vec4 colour) { std::fill_n(colour_data(), pixel_count(), to_rgba8(colour)); }

void Framebuffer::use_colour_memory(Rgba8* pixels) {
    external_colour_ = pixels;
    if (pixels) {
        decltype(colour_)().swap(colour_);  // frees its memory
    } else if (colour_.empty()) {
        colour_.resize(pixel_count());
    }
}

void Framebuffer::clear_depth(float depth) { std::fill(depth_.begin(), depth_.end(), depth); }

}  // namespace facet
