#include "strata/image/image_io.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/memory_budget.h"
#include "strata/image/image_ops.h"
#include "strata/image/quantize.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <jpeglib.h>
#include <png.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>
#pragma GCC diagnostic pop

namespace fs = std::filesystem;

namespace strata {

namespace {

using Bytes = std::vector<unsigned char>;

[[noreturn]] void fail(ErrorKind kind, const fs::path& path, const std::string& what) {
    throw Error(kind, path.string() + ": " + what);
}

std::string dimensions(long long width, long long height) {
    return std::to_string(width) + " x " + std::to_string(height);
}

// Applied to every format's header before any pixel memory exists, so that a hostile or corrupt header
// costs nothing.
void checkDimensions(const fs::path& path, ImageFormat format, long long width, long long height) {
    if (width <= 0 || height <= 0)
        fail(ErrorKind::InvalidInput, path,
             std::string(toString(format)) + " header gives a zero width or height (" +
                 dimensions(width, height) + ")");
    if (width > Image::kMaxDimension || height > Image::kMaxDimension)
        fail(ErrorKind::Unsupported, path,
             std::string(toString(format)) + " image is " + dimensions(width, height) +
                 ", larger than the maximum of " + std::to_string(Image::kMaxDimension) +
                 " texels in either direction");
}

// The budget check of a reader: the decoded float image plus `extraBytes` of decoder buffers, before
// either exists. The message names the file and what its header declares.
void checkReadBudget(const fs::path& path, ImageFormat format, long long width, long long height,
                     int channels, std::uint64_t extraBytes) {
    const std::uint64_t image = saturatingMultiply(
        saturatingMultiply(static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height)),
        static_cast<std::uint64_t>(channels) * sizeof(float));
    reserveOrThrow(image + extraBytes, path.string() + ": a " + dimensions(width, height) + " " +
                                           toString(format) + " of " + std::to_string(channels) +
                                           (channels == 1 ? " channel" : " channels"));
}

unsigned readLe16(const Bytes& b, std::size_t at) {
    return b[at] | (b[at + 1] << 8);
}
std::uint32_t readLe32(const Bytes& b, std::size_t at) {
    return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
           static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}

bool startsWith(const Bytes& bytes, std::initializer_list<unsigned char> magic) {
    return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
}

// A file that is a proper prefix of a signature: a truncated image rather than an unknown format.
bool isPrefixOf(const Bytes& bytes, std::initializer_list<unsigned char> magic) {
    return bytes.size() >= 2 && bytes.size() < magic.size() &&
           std::equal(bytes.begin(), bytes.end(), magic.begin());
}

constexpr std::initializer_list<unsigned char> kPngMagic = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::initializer_list<unsigned char> kExrMagic = {0x76, 0x2f, 0x31, 0x01};

// TGA has no signature; accept only a header whose every field is one that the format allows, so that
// text or an unknown binary is not mistaken for it.
bool looksLikeTga(const Bytes& b) {
    if (b.size() < 18) return false;
    const unsigned colorMapType = b[1];
    const unsigned imageType = b[2];
    const unsigned bitsPerPixel = b[16];
    const bool colorMapped = imageType == 1 || imageType == 9;
    const bool trueColor = imageType == 2 || imageType == 10;
    const bool gray = imageType == 3 || imageType == 11;
    if (colorMapType > 1 || !(colorMapped || trueColor || gray)) return false;
    if (colorMapped != (colorMapType == 1)) return false;
    if (colorMapped) return bitsPerPixel == 8 || bitsPerPixel == 16;
    if (gray) return bitsPerPixel == 8 || bitsPerPixel == 16;
    return bitsPerPixel == 15 || bitsPerPixel == 16 || bitsPerPixel == 24 || bitsPerPixel == 32;
}

ImageFormat detectFormat(const fs::path& path, const Bytes& bytes) {
    if (bytes.empty()) fail(ErrorKind::InvalidInput, path, "empty file");
    if (startsWith(bytes, kPngMagic)) return ImageFormat::Png;
    if (startsWith(bytes, {0xff, 0xd8, 0xff})) return ImageFormat::Jpeg;
    if (startsWith(bytes, kExrMagic)) return ImageFormat::Exr;
    if (startsWith(bytes, {'B', 'M'}) && bytes.size() >= 26) return ImageFormat::Bmp;
    if (isPrefixOf(bytes, kPngMagic))
        fail(ErrorKind::InvalidInput, path, "truncated PNG file (shorter than its signature)");
    if (isPrefixOf(bytes, kExrMagic))
        fail(ErrorKind::InvalidInput, path, "truncated EXR file (shorter than its signature)");
    if (startsWith(bytes, {'B', 'M'}))
        fail(ErrorKind::InvalidInput, path, "truncated BMP file (shorter than its header)");
    // Recognised formats that Strata does not read: say so rather than "not an image".
    const auto unsupported = [&](const char* name) {
        fail(ErrorKind::Unsupported, path,
             std::string(name) + " images are not supported (use PNG, EXR, JPEG, TGA or BMP)");
    };
    if (startsWith(bytes, {'G', 'I', 'F', '8'})) unsupported("GIF");
    if (startsWith(bytes, {'I', 'I', 0x2a, 0x00}) || startsWith(bytes, {'M', 'M', 0x00, 0x2a}))
        unsupported("TIFF");
    if (bytes.size() >= 12 && startsWith(bytes, {'R', 'I', 'F', 'F'}) &&
        std::memcmp(&bytes[8], "WEBP", 4) == 0)
        unsupported("WebP");
    if (startsWith(bytes, {'8', 'B', 'P', 'S'})) unsupported("Photoshop");
    if (startsWith(bytes, {'D', 'D', 'S', ' '})) unsupported("DDS");
    if (startsWith(bytes, {'#', '?', 'R', 'A', 'D', 'I', 'A', 'N', 'C', 'E'}) ||
        startsWith(bytes, {'#', '?', 'R', 'G', 'B', 'E'}))
        unsupported("Radiance HDR");
    // Netpbm: 'P', a type digit, whitespace.
    if (bytes.size() >= 3 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '7' && std::isspace(bytes[2]))
        unsupported("Netpbm");
    if (looksLikeTga(bytes)) return ImageFormat::Tga;
    fail(ErrorKind::InvalidInput, path, "not an image (unrecognised content)");
}

// ---------------------------------------------------------------------------------------------------------
// PNG through libpng.
//
// libpng reports errors by calling an error function that must not return; we longjmp back to the
// setjmp in the stage that called libpng. To keep that well-defined in C++, every function that calls
// setjmp holds only trivially destructible locals, and all owning objects (the png structs, buffers, the
// Image) live in the callers, created before and destroyed after the jump.

struct PngErrorState {
    char error[256] = {};
    // libpng often says why in a warning just before a generic error ("Image width is zero in IHDR",
    // then "Invalid IHDR data"), so the last warning goes into the message too.
    char warning[256] = {};

    std::string message() const {
        return warning[0] ? std::string(error) + " (" + warning + ")" : std::string(error);
    }
};

[[noreturn]] void pngError(png_structp png, png_const_charp message) {
    auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
    std::snprintf(state->error, sizeof state->error, "%s", message);
    png_longjmp(png, 1);
}

// libpng recovers from what it only warns about (e.g. a bad CRC in an ancillary chunk); library code
// never prints, so the warning is kept for a later error message and otherwise dropped.
void pngWarning(png_structp png, png_const_charp message) {
    auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
    std::snprintf(state->warning, sizeof state->warning, "%s", message);
}

struct PngSource {
    const unsigned char* data;
    std::size_t size;
    std::size_t offset;
};

void pngReadFromMemory(png_structp png, png_bytep out, std::size_t length) {
    auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
    if (length > source->size - source->offset) png_error(png, "the file ends early");
    std::memcpy(out, source->data + source->offset, length);
    source->offset += length;
}

class PngReadStruct {
public:
    PngReadStruct(const Bytes& bytes) : mSource{bytes.data(), bytes.size(), 0} {
        mPng = png_create_read_struct(PNG_LIBPNG_VER_STRING, &mErrors, pngError, pngWarning);
        if (mPng) mInfo = png_create_info_struct(mPng);
        if (!mPng || !mInfo) throw std::bad_alloc();
    }
    ~PngReadStruct() { png_destroy_read_struct(&mPng, mInfo ? &mInfo : nullptr, nullptr); }
    PngReadStruct(const PngReadStruct&) = delete;
    PngReadStruct& operator=(const PngReadStruct&) = delete;

    png_structp png() const { return mPng; }
    png_infop info() const { return mInfo; }
    PngSource* source() { return &mSource; }
    std::string message() const { return mErrors.message(); }

private:
    PngErrorState mErrors;
    PngSource mSource;
    png_structp mPng = nullptr;
    png_infop mInfo = nullptr;
};

struct PngHeader {
    png_uint_32 width;
    png_uint_32 height;
    int channels;  // after expansion of palette, low-bit gray and tRNS
    int bitDepth;  // 8 or 16 after expansion
    bool interlaced;
};

// Stage 1: the chunks before the image data. Allocates nothing proportional to the image.
bool pngReadHeader(PngReadStruct& s, PngHeader* header) {
    if (setjmp(png_jmpbuf(s.png()))) return false;
    png_set_read_fn(s.png(), s.source(), pngReadFromMemory);
    png_read_info(s.png(), s.info());
    header->width = png_get_image_width(s.png(), s.info());
    header->height = png_get_image_height(s.png(), s.info());
    header->bitDepth = png_get_bit_depth(s.png(), s.info()) == 16 ? 16 : 8;
    header->interlaced = png_get_interlace_type(s.png(), s.info()) != PNG_INTERLACE_NONE;
    const int colorType = png_get_color_type(s.png(), s.info());
    const bool transparency = png_get_valid(s.png(), s.info(), PNG_INFO_tRNS) != 0;
    if (colorType == PNG_COLOR_TYPE_GRAY)
        header->channels = transparency ? 2 : 1;
    else if (colorType == PNG_COLOR_TYPE_GRAY_ALPHA)
        header->channels = 2;
    else if (colorType == PNG_COLOR_TYPE_RGB_ALPHA)
        header->channels = 4;
    else
        header->channels = transparency ? 4 : 3;  // RGB or palette
    return true;
}

struct PngLayout {
    int channels;
    int bitDepth;
    std::size_t rowBytes;
    int passes;
};

// Stage 2: ask libpng to expand everything to 8 or 16 bits per channel of gray(+alpha) or RGB(+alpha).
bool pngSetExpansion(PngReadStruct& s, PngLayout* layout) {
    if (setjmp(png_jmpbuf(s.png()))) return false;
    png_set_expand(s.png());  // palette -> RGB, 1/2/4-bit gray -> 8-bit, tRNS -> alpha
    layout->passes = png_set_interlace_handling(s.png());
    png_read_update_info(s.png(), s.info());
    layout->channels = png_get_channels(s.png(), s.info());
    layout->bitDepth = png_get_bit_depth(s.png(), s.info());
    layout->rowBytes = png_get_rowbytes(s.png(), s.info());
    return true;
}

void pngRowToFloat(const png_byte* row, std::size_t count, bool sixteen, float* out) {
    if (sixteen) {
        for (std::size_t i = 0; i < count; ++i)
            out[i] = static_cast<float>(row[2 * i] << 8 | row[2 * i + 1]) / 65535.0f;
    } else {
        for (std::size_t i = 0; i < count; ++i) out[i] = static_cast<float>(row[i]) / 255.0f;
    }
}

struct PngDecodePlan {
    png_bytep buffer;  // one row, or every row when interlaced (the passes fill rows in place)
    std::size_t rowBytes;
    int height;
    int passes;
    std::size_t valuesPerRow;
    bool sixteen;
    float* pixels;  // the Image's storage, rows top first like the file's
};

// Stage 3: the image data, converted to float row by row when the file is not interlaced, then the
// chunks after it (a file cut short anywhere is an error).
bool pngDecode(PngReadStruct& s, const PngDecodePlan& plan) {
    if (setjmp(png_jmpbuf(s.png()))) return false;
    const bool interlaced = plan.passes > 1;
    for (int pass = 0; pass < plan.passes; ++pass) {
        for (int y = 0; y < plan.height; ++y) {
            png_bytep row = plan.buffer + (interlaced ? static_cast<std::size_t>(y) * plan.rowBytes : 0);
            png_read_row(s.png(), row, nullptr);
            if (!interlaced)
                pngRowToFloat(row, plan.valuesPerRow, plan.sixteen,
                              plan.pixels + static_cast<std::size_t>(y) * plan.valuesPerRow);
        }
    }
    if (interlaced) {
        for (int y = 0; y < plan.height; ++y)
            pngRowToFloat(plan.buffer + static_cast<std::size_t>(y) * plan.rowBytes, plan.valuesPerRow,
                          plan.sixteen, plan.pixels + static_cast<std::size_t>(y) * plan.valuesPerRow);
    }
    png_read_end(s.png(), nullptr);
    return true;
}

PngHeader readPngHeader(const fs::path& path, PngReadStruct& s) {
    PngHeader header{};
    if (!pngReadHeader(s, &header))
        fail(ErrorKind::InvalidInput, path, "corrupt or truncated PNG: " + s.message());
    checkDimensions(path, ImageFormat::Png, header.width, header.height);
    return header;
}

ImageInfo pngInfo(const fs::path& path, const Bytes& bytes) {
    PngReadStruct s(bytes);
    const PngHeader header = readPngHeader(path, s);
    return {ImageFormat::Png, static_cast<int>(header.width), static_cast<int>(header.height),
            header.channels, header.bitDepth};
}

Image readPng(const fs::path& path, const Bytes& bytes) {
    PngReadStruct s(bytes);
    const PngHeader header = readPngHeader(path, s);
    PngLayout layout{};
    if (!pngSetExpansion(s, &layout)) fail(ErrorKind::InvalidInput, path, "corrupt PNG: " + s.message());
    // The expansion must produce what the header promised; anything else is a bug here, not bad input.
    STRATA_CHECK_EQ(layout.channels, header.channels);
    STRATA_CHECK_EQ(layout.bitDepth, header.bitDepth);

    const int width = static_cast<int>(header.width);
    const int height = static_cast<int>(header.height);
    // Deflate expands at most 1032:1, so image data larger than 1032 times the whole file (plus the
    // filter byte of every row) cannot be in it: a header that claims more is refused before decoding
    // (a 69-byte file claiming 16384^2 RGBA16 would otherwise cost 4 GiB before it fails).
    const std::uint64_t rawBytes =
        saturatingMultiply(layout.rowBytes + 1, static_cast<std::uint64_t>(height));
    if (rawBytes / 1032 > bytes.size())
        fail(ErrorKind::InvalidInput, path,
             "truncated PNG: the header declares " + dimensions(width, height) + " (" +
                 formatBytes(rawBytes) + " of image data), more than a " + std::to_string(bytes.size()) +
                 "-byte file can hold");
    checkReadBudget(path, ImageFormat::Png, width, height, layout.channels,
                    layout.rowBytes * (layout.passes > 1 ? static_cast<std::uint64_t>(height) : 1));
    Image image(width, height, layout.channels);
    std::vector<png_byte> buffer(layout.rowBytes *
                                 (layout.passes > 1 ? static_cast<std::size_t>(height) : 1));
    const PngDecodePlan plan{buffer.data(),
                             layout.rowBytes,
                             height,
                             layout.passes,
                             static_cast<std::size_t>(width) * static_cast<std::size_t>(layout.channels),
                             layout.bitDepth == 16,
                             image.pixels().data()};
    if (!pngDecode(s, plan)) fail(ErrorKind::InvalidInput, path, "corrupt or truncated PNG: " + s.message());
    return image;
}

// 8x8 Bayer matrix: thresholds (b + 0.5) / 64 cover (0, 1) evenly, so over any 8x8 block the average
// rounding error of a constant is below 1/128 LSB.
constexpr unsigned char kBayer8[8][8] = {{0, 32, 8, 40, 2, 34, 10, 42},  {48, 16, 56, 24, 50, 18, 58, 26},
                                         {12, 44, 4, 36, 14, 46, 6, 38}, {60, 28, 52, 20, 62, 30, 54, 22},
                                         {3, 35, 11, 43, 1, 33, 9, 41},  {51, 19, 59, 27, 49, 17, 57, 25},
                                         {15, 47, 7, 39, 13, 45, 5, 37}, {63, 31, 55, 23, 61, 29, 53, 21}};

// Clamped to [0, 1]; NaN counts as 0 (a NaN cannot be quantised and must not reach a cast).
double unitClamp(float v) {
    return v > 0.0f ? std::min(static_cast<double>(v), 1.0) : 0.0;
}

std::vector<png_byte> quantizeForPng(const Image& image, const PngWriteOptions& options) {
    const int channels = image.channels();
    const bool sixteen = options.bitDepth == PngBitDepth::Sixteen;
    std::vector<png_byte> data(image.texelCount() * static_cast<std::size_t>(channels) * (sixteen ? 2 : 1));
    std::size_t at = 0;
    for (int y = 0; y < image.height(); ++y) {
        const float* row = image.row(y);
        for (int x = 0; x < image.width(); ++x) {
            // round(v * 255) is floor(v * 255 + 0.5); the dither replaces the 0.5 by a threshold in (0, 1).
            const double offset = options.dither ? (kBayer8[y & 7][x & 7] + 0.5) / 64.0 : 0.5;
            for (int c = 0; c < channels; ++c) {
                const double v = unitClamp(row[x * channels + c]);
                if (sixteen) {
                    const unsigned q = toUnorm16(v);
                    data[at++] = static_cast<png_byte>(q >> 8);  // PNG stores 16-bit samples big-endian
                    data[at++] = static_cast<png_byte>(q & 0xff);
                } else {
                    data[at++] = static_cast<png_byte>(std::min(255.0, std::floor(v * 255.0 + offset)));
                }
            }
        }
    }
    return data;
}

struct PngEncodePlan {
    png_uint_32 width;
    png_uint_32 height;
    int bitDepth;
    int colorType;
    png_bytepp rows;
};

bool pngEncode(png_structp png, png_infop info, FILE* file, const PngEncodePlan& plan) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_init_io(png, file);
    png_set_IHDR(png, info, plan.width, plan.height, plan.bitDepth, plan.colorType, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, plan.rows);
    png_write_end(png, nullptr);
    return true;
}

class PngWriteStruct {
public:
    PngWriteStruct() {
        mPng = png_create_write_struct(PNG_LIBPNG_VER_STRING, &mErrors, pngError, pngWarning);
        if (mPng) mInfo = png_create_info_struct(mPng);
        if (!mPng || !mInfo) throw std::bad_alloc();
    }
    ~PngWriteStruct() { png_destroy_write_struct(&mPng, mInfo ? &mInfo : nullptr); }
    PngWriteStruct(const PngWriteStruct&) = delete;
    PngWriteStruct& operator=(const PngWriteStruct&) = delete;

    png_structp png() const { return mPng; }
    png_infop info() const { return mInfo; }
    std::string message() const { return mErrors.message(); }

private:
    PngErrorState mErrors;
    png_structp mPng = nullptr;
    png_infop mInfo = nullptr;
};

void writePngFile(const fs::path& dest, const fs::path& tmp, const Image& image,
                  const PngWriteOptions& options) {
    static constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                          PNG_COLOR_TYPE_RGB_ALPHA};
    std::vector<png_byte> data = quantizeForPng(image, options);
    const std::size_t rowBytes = data.size() / static_cast<std::size_t>(image.height());
    std::vector<png_bytep> rows(static_cast<std::size_t>(image.height()));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = data.data() + y * rowBytes;

    PngWriteStruct s;
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(tmp.c_str(), "wb"), std::fclose);
    if (!file) fail(ErrorKind::Io, dest, std::string("cannot create the file: ") + std::strerror(errno));
    const PngEncodePlan plan{static_cast<png_uint_32>(image.width()),
                             static_cast<png_uint_32>(image.height()), static_cast<int>(options.bitDepth),
                             kColorTypes[image.channels() - 1], rows.data()};
    if (!pngEncode(s.png(), s.info(), file.get(), plan))
        fail(ErrorKind::Io, dest, "cannot write the PNG: " + s.message());
    // Buffered data reaches the disk at fclose; a full disk shows up there.
    if (std::fclose(file.release()) != 0)
        fail(ErrorKind::Io, dest, std::string("cannot write the PNG: ") + std::strerror(errno));
}

// ---------------------------------------------------------------------------------------------------------
// JPEG, TGA and BMP through stb_image.

// stb_image reads past the end of a truncated uncompressed TGA or BMP as zeros without complaint, so the
// size that the header implies is checked here. Returns 0 where it cannot be known without decoding
// (run-length coded data).
std::size_t expectedUncompressedSize(ImageFormat format, const Bytes& b) {
    if (format == ImageFormat::Tga) {
        const unsigned imageType = b[2];
        if (imageType > 3) return 0;
        const std::size_t colorMapBytes = b[1] == 1 ? readLe16(b, 5) * ((b[7] + 7u) / 8u) : 0;
        return 18 + b[0] + colorMapBytes +
               std::size_t{readLe16(b, 12)} * readLe16(b, 14) * ((b[16] + 7u) / 8u);
    }
    if (format == ImageFormat::Bmp) {
        const std::uint32_t dataOffset = readLe32(b, 10);
        const std::uint32_t headerSize = readLe32(b, 14);
        long long width = 0;
        long long height = 0;
        unsigned bitsPerPixel = 0;
        if (headerSize == 12) {
            width = readLe16(b, 18);
            height = readLe16(b, 20);
            bitsPerPixel = readLe16(b, 24);
        } else {
            if (b.size() < 34) return b.size() + 1;
            width = static_cast<std::int32_t>(readLe32(b, 18));
            height = std::llabs(static_cast<std::int32_t>(readLe32(b, 22)));
            bitsPerPixel = readLe16(b, 28);
            const std::uint32_t compression = readLe32(b, 30);
            if (compression != 0 && compression != 3) return 0;  // BI_RGB and BI_BITFIELDS only
        }
        if (width <= 0 || height <= 0 || width > Image::kMaxDimension || height > Image::kMaxDimension)
            return 0;
        const auto stride = static_cast<std::size_t>((width * bitsPerPixel + 31) / 32 * 4);
        return dataOffset + stride * static_cast<std::size_t>(height);
    }
    return 0;
}

// The fewest bytes run-length coded TGA or BMP data can hold its header's image in: a TGA packet (1 byte
// and one pixel) repeats at most 128 pixels, a BMP RLE8/RLE4 pair (2 bytes) at most 255. A few bytes
// claiming a picture of 10^8 texels would otherwise be decoded (and allocated) before they run out.
// Returns 0 for other data.
std::uint64_t minimumRunLengthSize(ImageFormat format, const Bytes& b) {
    if (format == ImageFormat::Tga && b[2] >= 9 && b[2] <= 11) {
        const std::uint64_t pixels = std::uint64_t{readLe16(b, 12)} * readLe16(b, 14);
        return 18 + b[0] + (pixels + 127) / 128 * (1 + (b[16] + 7u) / 8u);
    }
    if (format == ImageFormat::Bmp && b.size() >= 34 && readLe32(b, 14) >= 40) {
        const std::uint32_t compression = readLe32(b, 30);
        if (compression != 1 && compression != 2) return 0;
        const auto width = static_cast<std::int32_t>(readLe32(b, 18));
        const std::int64_t height = std::llabs(static_cast<std::int32_t>(readLe32(b, 22)));
        if (width <= 0) return 0;
        const std::uint64_t pixels = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
        return readLe32(b, 10) + (pixels + 254) / 255 * 2;
    }
    return 0;
}

// A JPEG cut short loses its end-of-image marker; stb_image would decode the rest as grey. Walks the
// marker segments to the first start-of-scan (so that the EOI of an embedded thumbnail is not counted)
// and looks for an EOI after it. In entropy-coded data 0xFF is always followed by 0x00 or a restart
// marker, so FF D9 there is the real end.
bool jpegHasEnd(const Bytes& b) {
    std::size_t at = 2;
    while (at + 4 <= b.size()) {
        if (b[at] != 0xff) return false;
        const unsigned marker = b[at + 1];
        if (marker == 0xff) {
            ++at;
            continue;
        }
        if (marker == 0xda) break;
        if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) {
            at += 2;
            continue;
        }
        at += 2 + (b[at + 2] << 8 | b[at + 3]);
    }
    for (std::size_t i = at; i + 1 < b.size(); ++i)
        if (b[i] == 0xff && b[i + 1] == 0xd9) return true;
    return false;
}

ImageInfo stbInfo(const fs::path& path, ImageFormat format, const Bytes& bytes) {
    int width = 0;
    int height = 0;
    int channels = 0;
    if (!stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &width, &height, &channels))
        fail(ErrorKind::InvalidInput, path,
             std::string("corrupt ") + toString(format) + " header (" + stbi_failure_reason() + ")");
    checkDimensions(path, format, width, height);
    if (channels < 1 || channels > 4)
        fail(ErrorKind::Unsupported, path,
             std::string(toString(format)) + " with " + std::to_string(channels) + " channels");
    return {format, width, height, channels, 8};
}

Image readStb(const fs::path& path, ImageFormat format, const Bytes& bytes) {
    const ImageInfo info = stbInfo(path, format, bytes);
    const std::size_t expected = expectedUncompressedSize(format, bytes);
    if (expected > bytes.size())
        fail(ErrorKind::InvalidInput, path,
             std::string("truncated ") + toString(format) + " data (the file ends early)");
    if (minimumRunLengthSize(format, bytes) > bytes.size())
        fail(ErrorKind::InvalidInput, path,
             std::string("truncated ") + toString(format) + " data: the header declares " +
                 dimensions(info.width, info.height) + ", more than its " + std::to_string(bytes.size()) +
                 "-byte file can hold even run-length coded");
    // stb_image's 8-bit buffer, then the float image.
    checkReadBudget(path, format, info.width, info.height, info.channels,
                    static_cast<std::uint64_t>(info.width) * static_cast<std::uint64_t>(info.height) *
                        static_cast<std::uint64_t>(info.channels));
    int width = 0;
    int height = 0;
    int channels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &width, &height, &channels, 0),
        stbi_image_free);
    if (!data)
        fail(ErrorKind::InvalidInput, path,
             std::string("corrupt ") + toString(format) + " data (" + stbi_failure_reason() + ")");
    if (width != info.width || height != info.height || channels != info.channels)
        fail(ErrorKind::InvalidInput, path,
             std::string("corrupt ") + toString(format) + ": the header and the data disagree");
    // stb_image returns rows top first for every format (it flips bottom-up BMP and TGA itself).
    Image image(width, height, channels);
    const std::span<float> pixels = image.pixels();
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(data.get()[i]) / 255.0f;
    return image;
}

// ---------------------------------------------------------------------------------------------------------
// JPEG through libjpeg-turbo, whose error manager reports corrupt data and a premature end, where
// stb_image decodes a damaged file as grey without a word. Like libpng above, errors longjmp back to
// the stage that called libjpeg; those stages hold only trivially destructible locals. Every libjpeg
// warning (corrupt data, premature end, extraneous bytes, an inconsistent progression) is an error.

struct JpegErrorState {
    jpeg_error_mgr manager;  // first: libjpeg's cinfo->err points here
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpegErrorExit(j_common_ptr cinfo) {
    auto* state = reinterpret_cast<JpegErrorState*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, state->message);
    std::longjmp(state->jump, 1);
}

void jpegEmitMessage(j_common_ptr cinfo, int level) {
    if (level < 0) jpegErrorExit(cinfo);  // a warning: the data is corrupt or cut short
}

class JpegReadStruct {
public:
    JpegReadStruct() {
        mCinfo.err = jpeg_std_error(&mErrors.manager);
        mErrors.manager.error_exit = jpegErrorExit;
        mErrors.manager.emit_message = jpegEmitMessage;
        mErrors.message[0] = '\0';
    }
    ~JpegReadStruct() {
        if (mCreated) jpeg_destroy_decompress(&mCinfo);
    }
    JpegReadStruct(const JpegReadStruct&) = delete;
    JpegReadStruct& operator=(const JpegReadStruct&) = delete;

    jpeg_decompress_struct* cinfo() { return &mCinfo; }
    std::jmp_buf& jump() { return mErrors.jump; }
    std::string message() const { return mErrors.message; }
    void setCreated() { mCreated = true; }

private:
    jpeg_decompress_struct mCinfo{};
    JpegErrorState mErrors{};
    bool mCreated = false;
};

struct JpegHeader {
    int width;
    int height;
    int components;
    bool cmyk;
    bool arithmetic;
};

// Stage 1: the markers up to the first scan. Allocates nothing proportional to the image.
bool jpegReadHeader(JpegReadStruct& s, const Bytes& bytes, JpegHeader* header) {
    if (setjmp(s.jump())) return false;
    jpeg_create_decompress(s.cinfo());
    s.setCreated();
    jpeg_mem_src(s.cinfo(), bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(s.cinfo(), TRUE);
    header->width = static_cast<int>(s.cinfo()->image_width);
    header->height = static_cast<int>(s.cinfo()->image_height);
    header->components = s.cinfo()->num_components;
    header->cmyk = s.cinfo()->jpeg_color_space == JCS_CMYK || s.cinfo()->jpeg_color_space == JCS_YCCK;
    header->arithmetic = s.cinfo()->arith_code != FALSE;
    return true;
}

struct JpegDecodePlan {
    unsigned char* row;  // one output row of width * channels bytes
    int width;
    int height;
    int channels;
    float* pixels;
};

// Stage 2: every scanline, then the markers to the end of the image.
bool jpegDecode(JpegReadStruct& s, const JpegDecodePlan& plan) {
    if (setjmp(s.jump())) return false;
    s.cinfo()->out_color_space = plan.channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_start_decompress(s.cinfo());
    const auto values = static_cast<std::size_t>(plan.width) * static_cast<std::size_t>(plan.channels);
    while (s.cinfo()->output_scanline < s.cinfo()->output_height) {
        const auto y = static_cast<std::size_t>(s.cinfo()->output_scanline);
        JSAMPROW rows[1] = {plan.row};
        jpeg_read_scanlines(s.cinfo(), rows, 1);
        float* out = plan.pixels + y * values;
        for (std::size_t i = 0; i < values; ++i) out[i] = static_cast<float>(plan.row[i]) / 255.0f;
    }
    jpeg_finish_decompress(s.cinfo());
    return true;
}

Image readJpeg(const fs::path& path, const Bytes& bytes) {
    if (!jpegHasEnd(bytes)) fail(ErrorKind::InvalidInput, path, "truncated JPEG data (the file ends early)");
    JpegReadStruct s;
    JpegHeader header{};
    if (!jpegReadHeader(s, bytes, &header))
        fail(ErrorKind::InvalidInput, path, "corrupt JPEG header: " + s.message());
    checkDimensions(path, ImageFormat::Jpeg, header.width, header.height);
    if (header.cmyk || (header.components != 1 && header.components != 3))
        fail(ErrorKind::Unsupported, path,
             "JPEG with " + std::to_string(header.components) + " components" +
                 (header.cmyk ? " (CMYK)" : "") + " (only grayscale and colour are read)");
    // Every 8 x 8 block of the first component costs at least one bit of entropy-coded data (its DC
    // code) with Huffman coding, so a file smaller than that cannot hold the image its header declares.
    // (Arithmetic coding can go below a bit per block, so it is not bounded here.)
    const std::uint64_t blocks = static_cast<std::uint64_t>((header.width + 7) / 8) *
                                 static_cast<std::uint64_t>((header.height + 7) / 8);
    if (!header.arithmetic && blocks / 8 > bytes.size())
        fail(ErrorKind::InvalidInput, path,
             "truncated JPEG: the header declares " + dimensions(header.width, header.height) +
                 ", which needs at least " + std::to_string(blocks / 8) + " bytes of data; the file has " +
                 std::to_string(bytes.size()));
    const int channels = header.components == 1 ? 1 : 3;
    checkReadBudget(path, ImageFormat::Jpeg, header.width, header.height, channels,
                    static_cast<std::uint64_t>(header.width) * 16u * static_cast<std::uint64_t>(channels));
    Image image(header.width, header.height, channels);
    std::vector<unsigned char> row(static_cast<std::size_t>(header.width) *
                                   static_cast<std::size_t>(channels));
    const JpegDecodePlan plan{row.data(), header.width, header.height, channels, image.pixels().data()};
    if (!jpegDecode(s, plan))
        fail(ErrorKind::InvalidInput, path, "corrupt or truncated JPEG: " + s.message());
    return image;
}

// ---------------------------------------------------------------------------------------------------------
// OpenEXR through tinyexr.

std::string takeExrError(const char* err) {
    std::string message = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.pop_back();
    return message;
}

ErrorKind exrErrorKind(int code) {
    return code == TINYEXR_ERROR_UNSUPPORTED_FORMAT || code == TINYEXR_ERROR_UNSUPPORTED_FEATURE
               ? ErrorKind::Unsupported
               : ErrorKind::InvalidInput;
}

class ExrHeader {
public:
    ExrHeader() { InitEXRHeader(&mHeader); }
    ~ExrHeader() { FreeEXRHeader(&mHeader); }
    ExrHeader(const ExrHeader&) = delete;
    ExrHeader& operator=(const ExrHeader&) = delete;
    EXRHeader* get() { return &mHeader; }
    EXRHeader* operator->() { return &mHeader; }

private:
    EXRHeader mHeader;
};

class ExrImage {
public:
    ExrImage() { InitEXRImage(&mImage); }
    ~ExrImage() { FreeEXRImage(&mImage); }
    ExrImage(const ExrImage&) = delete;
    ExrImage& operator=(const ExrImage&) = delete;
    EXRImage* get() { return &mImage; }
    EXRImage* operator->() { return &mImage; }

private:
    EXRImage mImage;
};

// Which of the file's channels become the Image's, in order: Y, YA, RGB or RGBA, or a single channel
// of any name (a depth or height map).
std::vector<int> exrChannelOrder(const fs::path& path, EXRHeader& header) {
    const auto find = [&](const char* name) {
        for (int i = 0; i < header.num_channels; ++i)
            if (std::strcmp(header.channels[i].name, name) == 0) return i;
        return -1;
    };
    const int r = find("R"), g = find("G"), b = find("B"), a = find("A"), y = find("Y");
    std::vector<int> order;
    if (r >= 0 && g >= 0 && b >= 0)
        order = {r, g, b};
    else if (y >= 0)
        order = {y};
    else if (header.num_channels == 1)
        order = {0};
    if (!order.empty() && a >= 0) order.push_back(a);
    if (order.empty()) {
        std::string names;
        for (int i = 0; i < header.num_channels; ++i)
            names += std::string(names.empty() ? "" : ", ") + header.channels[i].name;
        fail(ErrorKind::Unsupported, path, "EXR channels (" + names + ") are not Y, YA, RGB or RGBA");
    }
    for (int i : order)
        if (header.channels[i].x_sampling != 1 || header.channels[i].y_sampling != 1)
            fail(ErrorKind::Unsupported, path,
                 std::string("EXR channel ") + header.channels[i].name + " is subsampled");
    return order;
}

struct ExrParsed {
    int width;
    int height;
    std::vector<int> order;
    int bitDepth;
};

ExrParsed parseExrHeader(const fs::path& path, const Bytes& bytes, ExrHeader& header) {
    EXRVersion version{};
    if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS)
        fail(ErrorKind::InvalidInput, path, "corrupt or truncated EXR version header");
    if (version.multipart || version.non_image)
        fail(ErrorKind::Unsupported, path, "multi-part and deep EXR files are not supported");
    if (version.tiled)
        fail(ErrorKind::Unsupported, path, "tiled EXR files are not supported (only scanline)");
    const char* err = nullptr;
    const int code = ParseEXRHeaderFromMemory(header.get(), &version, bytes.data(), bytes.size(), &err);
    if (code != TINYEXR_SUCCESS) fail(exrErrorKind(code), path, "corrupt EXR header: " + takeExrError(err));
    const EXRBox2i& window = header->data_window;
    const long long width = static_cast<long long>(window.max_x) - window.min_x + 1;
    const long long height = static_cast<long long>(window.max_y) - window.min_y + 1;
    checkDimensions(path, ImageFormat::Exr, width, height);
    ExrParsed parsed{static_cast<int>(width), static_cast<int>(height), exrChannelOrder(path, *header.get()),
                     16};
    for (int i : parsed.order)
        if (header->pixel_types[i] != TINYEXR_PIXELTYPE_HALF) parsed.bitDepth = 32;
    return parsed;
}

ImageInfo exrInfo(const fs::path& path, const Bytes& bytes) {
    ExrHeader header;
    const ExrParsed parsed = parseExrHeader(path, bytes, header);
    return {ImageFormat::Exr, parsed.width, parsed.height, static_cast<int>(parsed.order.size()),
            parsed.bitDepth};
}

Image readExr(const fs::path& path, const Bytes& bytes) {
    ExrHeader header;
    const ExrParsed parsed = parseExrHeader(path, bytes, header);
    // Halves are widened to float by tinyexr; UINT channels stay integers and are converted below.
    for (int i = 0; i < header->num_channels; ++i)
        if (header->pixel_types[i] == TINYEXR_PIXELTYPE_HALF)
            header->requested_pixel_types[i] = TINYEXR_PIXELTYPE_FLOAT;
    // tinyexr's float plane of every channel in the file, then the float image.
    checkReadBudget(path, ImageFormat::Exr, parsed.width, parsed.height,
                    static_cast<int>(parsed.order.size()),
                    saturatingMultiply(static_cast<std::uint64_t>(parsed.width) *
                                           static_cast<std::uint64_t>(parsed.height) * sizeof(float),
                                       static_cast<std::uint64_t>(header->num_channels)));
    ExrImage exr;
    // tinyexr (1.0.1) frees the image itself when the pixel data is invalid, but only the channel planes
    // that num_channels counts, which it sets only on success; setting it first makes that cleanup
    // complete (tinyexr never resets it). The pointers it frees are not cleared, so after a failure the
    // struct is forgotten rather than freed a second time.
    exr->num_channels = header->num_channels;
    const char* err = nullptr;
    const int code = LoadEXRImageFromMemory(exr.get(), header.get(), bytes.data(), bytes.size(), &err);
    if (code != TINYEXR_SUCCESS) {
        InitEXRImage(exr.get());
        fail(exrErrorKind(code), path, "corrupt or truncated EXR data: " + takeExrError(err));
    }
    if (exr->width != parsed.width || exr->height != parsed.height || !exr->images)
        fail(ErrorKind::InvalidInput, path, "corrupt EXR: the header and the data disagree");

    const int channels = static_cast<int>(parsed.order.size());
    Image image(parsed.width, parsed.height, channels);
    const std::span<float> pixels = image.pixels();
    for (int c = 0; c < channels; ++c) {
        const int source = parsed.order[static_cast<std::size_t>(c)];
        const unsigned char* plane = exr->images[source];
        const bool isUint = header->requested_pixel_types[source] == TINYEXR_PIXELTYPE_UINT;
        for (std::size_t i = 0; i < image.texelCount(); ++i) {
            float value = 0.0f;
            if (isUint) {
                std::uint32_t u = 0;
                std::memcpy(&u, plane + i * sizeof u, sizeof u);
                value = static_cast<float>(u);
            } else {
                std::memcpy(&value, plane + i * sizeof value, sizeof value);
            }
            pixels[i * static_cast<std::size_t>(channels) + static_cast<std::size_t>(c)] = value;
        }
    }
    // NaN or infinity is no depth, height or normal: refused here rather than read as 0 later. The
    // first one in row-major order (rows top first) is named.
    const auto bad = std::find_if(pixels.begin(), pixels.end(), [](float v) { return !std::isfinite(v); });
    if (bad != pixels.end()) {
        const auto at = static_cast<std::size_t>(bad - pixels.begin());
        const std::size_t texel = at / static_cast<std::size_t>(channels);
        const int source = parsed.order[at % static_cast<std::size_t>(channels)];
        fail(ErrorKind::InvalidInput, path,
             "EXR channel " + std::string(header->channels[source].name) + " holds " +
                 formatNumber(static_cast<double>(*bad)) + " at column " +
                 std::to_string(texel % static_cast<std::size_t>(parsed.width)) + ", row " +
                 std::to_string(texel / static_cast<std::size_t>(parsed.width)) +
                 " (row 0 is the top); only finite values are read");
    }
    return image;
}

void writeExrFile(const fs::path& dest, const fs::path& tmp, const Image& image) {
    // OpenEXR readers expect channels sorted by name, hence A, B, G, R.
    static const std::vector<std::pair<const char*, int>> kLayouts[] = {
        {{"Y", 0}},
        {{"A", 1}, {"Y", 0}},
        {{"B", 2}, {"G", 1}, {"R", 0}},
        {{"A", 3}, {"B", 2}, {"G", 1}, {"R", 0}}};
    const auto& layout = kLayouts[image.channels() - 1];
    const int count = static_cast<int>(layout.size());

    std::vector<std::vector<float>> planes(layout.size(), std::vector<float>(image.texelCount()));
    std::vector<unsigned char*> planePointers(layout.size());
    std::vector<EXRChannelInfo> channelInfos(layout.size());
    std::vector<int> pixelTypes(layout.size(), TINYEXR_PIXELTYPE_FLOAT);
    const std::span<const float> pixels = image.pixels();
    for (std::size_t k = 0; k < layout.size(); ++k) {
        for (std::size_t i = 0; i < image.texelCount(); ++i)
            planes[k][i] = pixels[i * static_cast<std::size_t>(image.channels()) +
                                  static_cast<std::size_t>(layout[k].second)];
        planePointers[k] = reinterpret_cast<unsigned char*>(planes[k].data());
        std::memset(&channelInfos[k], 0, sizeof(EXRChannelInfo));
        std::snprintf(channelInfos[k].name, sizeof channelInfos[k].name, "%s", layout[k].first);
    }

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = count;
    header.channels = channelInfos.data();
    header.pixel_types = pixelTypes.data();
    header.requested_pixel_types = pixelTypes.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    EXRImage exr;
    InitEXRImage(&exr);
    exr.images = planePointers.data();
    exr.width = image.width();
    exr.height = image.height();
    exr.num_channels = count;

    unsigned char* memory = nullptr;
    const char* err = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
    std::unique_ptr<unsigned char, void (*)(void*)> owned(memory, std::free);
    if (size == 0) fail(ErrorKind::Runtime, dest, "cannot encode the EXR: " + takeExrError(err));

    std::ofstream out(tmp, std::ios::binary);
    if (!out) fail(ErrorKind::Io, dest, std::string("cannot create the file: ") + std::strerror(errno));
    out.write(reinterpret_cast<const char*>(owned.get()), static_cast<std::streamsize>(size));
    out.close();
    if (!out) fail(ErrorKind::Io, dest, "cannot write the EXR");
}

struct LoadedFile {
    Bytes bytes;
    ImageFormat format;
};

LoadedFile loadFile(const fs::path& path) {
    LoadedFile file{readFileBytes(path), ImageFormat::Png};
    file.format = detectFormat(path, file.bytes);
    return file;
}

}  // namespace

const char* toString(ImageFormat format) {
    switch (format) {
        case ImageFormat::Png:
            return "PNG";
        case ImageFormat::Jpeg:
            return "JPEG";
        case ImageFormat::Tga:
            return "TGA";
        case ImageFormat::Bmp:
            return "BMP";
        case ImageFormat::Exr:
            return "EXR";
    }
    return "unknown";
}

ImageInfo readImageInfo(const fs::path& path) {
    const LoadedFile file = loadFile(path);
    switch (file.format) {
        case ImageFormat::Png:
            return pngInfo(path, file.bytes);
        case ImageFormat::Exr:
            return exrInfo(path, file.bytes);
        case ImageFormat::Jpeg:
        case ImageFormat::Tga:
        case ImageFormat::Bmp:
            return stbInfo(path, file.format, file.bytes);
    }
    fail(ErrorKind::Unsupported, path, "unknown image format");
}

Image readImage(const fs::path& path) {
    const LoadedFile file = loadFile(path);
    switch (file.format) {
        case ImageFormat::Png:
            return readPng(path, file.bytes);
        case ImageFormat::Exr:
            return readExr(path, file.bytes);
        case ImageFormat::Jpeg:
            return readJpeg(path, file.bytes);
        case ImageFormat::Tga:
        case ImageFormat::Bmp:
            return readStb(path, file.format, file.bytes);
    }
    fail(ErrorKind::Unsupported, path, "unknown image format");
}

Image readScalarMap(const fs::path& path, std::string* note) {
    return toScalarMap(readImage(path), path, note);
}

Image toScalarMap(Image image, const fs::path& path, std::string* note) {
    switch (image.channels()) {
        case 1:
            return image;
        case 2:
            return extractChannel(image, 0);
        default:
            if (note)
                *note = path.string() + ": " + (image.channels() == 3 ? "RGB" : "RGBA") +
                        " image read as a scalar map through its luminance (Rec. 709)" +
                        (image.channels() == 4 ? "; alpha ignored" : "");
            return luminance(image);
    }
}

void writePng(const fs::path& path, const Image& image, const PngWriteOptions& options) {
    STRATA_CHECK(!image.empty());
    writeFileAtomic(path, [&](const fs::path& tmp) { writePngFile(path, tmp, image, options); });
}

void writeExr(const fs::path& path, const Image& image) {
    STRATA_CHECK(!image.empty());
    writeFileAtomic(path, [&](const fs::path& tmp) { writeExrFile(path, tmp, image); });
}

void writeJpeg(const fs::path& path, const Image& image, int quality) {
    STRATA_CHECK(!image.empty());
    STRATA_CHECK(quality >= 1 && quality <= 100);
    // JPEG has no alpha: a gray+alpha or RGBA image is written as its gray or RGB channels.
    const Image colour = image.channels() == 2   ? extractChannel(image, 0)
                         : image.channels() == 4 ? toRgb(image)
                                                 : image;
    const std::vector<png_byte> data = quantizeForPng(colour, PngWriteOptions{PngBitDepth::Eight, true});
    writeFileAtomic(path, [&](const fs::path& tmp) {
        if (stbi_write_jpg(tmp.c_str(), colour.width(), colour.height(), colour.channels(), data.data(),
                           quality) == 0)
            fail(ErrorKind::Io, path, "cannot write the JPEG");
    });
}

std::optional<ImageFormat> outputFormatOf(const fs::path& path) {
    const std::string ext = lowerCaseExtension(path);
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".exr") return ImageFormat::Exr;
    if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::Jpeg;
    return std::nullopt;
}

ImageFormat checkOutputExtension(const fs::path& path, const std::string& flag,
                                 std::initializer_list<ImageFormat> allowed) {
    const std::optional<ImageFormat> format = outputFormatOf(path);
    for (ImageFormat a : allowed)
        if (format && *format == a) return a;
    std::string names;
    std::size_t i = 0;
    for (ImageFormat a : allowed) {
        names += i == 0 ? "" : (i + 1 == allowed.size() ? " or " : ", ");
        names += a == ImageFormat::Png ? ".png" : a == ImageFormat::Exr ? ".exr" : ".jpg";
        ++i;
    }
    const std::string ext = lowerCaseExtension(path);
    throw Error(ErrorKind::Usage, flag + " " + path.string() + ": cannot write " +
                                      (ext.empty() ? std::string("a file without an extension") : ext) +
                                      "; use " + names);
}

void writeImage(const fs::path& path, const Image& image, const PngWriteOptions& options) {
    const std::optional<ImageFormat> format = outputFormatOf(path);
    if (format == ImageFormat::Png) return writePng(path, image, options);
    if (format == ImageFormat::Exr) return writeExr(path, image);
    if (format == ImageFormat::Jpeg) return writeJpeg(path, image);
    fail(ErrorKind::Unsupported, path,
         "cannot write '" + lowerCaseExtension(path) + "' files: the extension must be .png, .exr or .jpg");
}

}  // namespace strata
