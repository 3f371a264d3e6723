"""A small PNG reader for the tests (8-bit greyscale, RGB and RGBA, 16-bit too, not interlaced): zlib and
NumPy only, independent of facet's own PNG code (libspng), so that comparing its pixels with an
array facet rendered compares facet's two outputs, not one decoder with itself."""
import struct
import zlib

import numpy as np

_CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}


def read_png(path) -> np.ndarray:
    """The image as an (H, W, C) array, first row at the top: uint8, or uint16 for 16-bit PNGs."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat.append(chunk)
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = header
    if depth not in (8, 16) or interlace != 0 or colour not in _CHANNELS:
        raise ValueError(f"{path}: only 8- and 16-bit, non-interlaced grey, RGB or RGBA PNGs are read here")
    channels = _CHANNELS[colour]
    bpp = channels * depth // 8  # the filters work on bytes, a whole pixel apart
    stride = width * bpp
    raw = zlib.decompress(b"".join(idat))
    out = np.zeros((height, stride), np.uint8)
    prev = np.zeros(stride, np.int32)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        line = np.frombuffer(raw, np.uint8, stride, start + 1).astype(np.int32)
        if kind == 0:
            cur = line
        elif kind == 1:  # Sub: a running sum along each channel
            cur = np.cumsum(line.reshape(width, bpp), axis=0).reshape(stride) & 255
        elif kind == 2:  # Up
            cur = (line + prev) & 255
        elif kind in (3, 4):  # Average, Paeth: pixel by pixel, each from the one before
            cur = np.zeros(stride, np.int32)
            left = np.zeros(bpp, np.int32)
            up_left = np.zeros(bpp, np.int32)
            for x in range(width):
                s = slice(x * bpp, (x + 1) * bpp)
                up = prev[s]
                if kind == 3:
                    pred = (left + up) // 2
                else:
                    p = left + up - up_left
                    pa, pb, pc = np.abs(p - left), np.abs(p - up), np.abs(p - up_left)
                    pred = np.where((pa <= pb) & (pa <= pc), left, np.where(pb <= pc, up, up_left))
                cur[s] = (line[s] + pred) & 255
                left, up_left = cur[s], up
        else:
            raise ValueError(f"{path}: bad filter type {kind} in row {y}")
        out[y] = cur
        prev = cur
    if depth == 16:  # big-endian samples
        pairs = out.reshape(height, width, channels, 2).astype(np.uint16)
        return (pairs[..., 0] << 8) | pairs[..., 1]
    return out.reshape(height, width, channels)
