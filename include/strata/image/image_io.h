// Reading and writing image files.
//
// Readers: PNG 8/16-bit (gray, gray+alpha, RGB, RGBA, and palette, expanded) through libpng;
// JPEG through libjpeg-turbo (every warning it gives about corrupt or missing data is an error); TGA and
// BMP through stb_image (Debian's libstb); OpenEXR through tinyexr. The format is
// recognised from the file's first bytes, not its extension, so a text file renamed `.png` is reported
// as "not an image". Values come back as floats in [0, 1] (8-bit / 255, 16-bit / 65535), EXR as stored.
// Rows are top first, as in the file and as strata::Image stores them (CONVENTIONS §1). PNG samples are
// taken as stored: gAMA/sRGB/iCCP chunks are not applied. EXR: single-part scanline files; channels
// Y, Y+A, R+G+B or R+G+B+A (or one channel of any name) become 1, 2, 3 or 4 channels; half is widened
// to float. GIF, TIFF, WebP, Photoshop, DDS, Radiance HDR and Netpbm are recognised and refused as
// Unsupported.
//
// Failure contract: every failure throws strata::Error whose message starts with the file's path
// and says what is wrong:
//   ErrorKind::Io           missing file, a directory, unreadable, cannot write;
//   ErrorKind::InvalidInput empty file, not an image, corrupt or truncated data, zero width or height,
//                           a PNG or JPEG header declaring more data than the file can hold (checked
//                           before decoding), NaN or infinity in an EXR (the first texel is named);
//   ErrorKind::Unsupported  a recognised but unsupported format or variant, or an image larger than
//                           Image::kMaxDimension in either direction, refused from the header before
//                           any pixel memory is allocated; an image whose decoding needs more than
//                           the memory budget (strata/core/memory_budget.h), refused likewise.
// Writers are atomic (temporary file, then rename): a failed write leaves nothing behind.
#pragma once

#include "strata/image/image.h"

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>

namespace strata {

enum class ImageFormat { Png, Jpeg, Tga, Bmp, Exr };

struct ImageInfo {
    ImageFormat format;
    int width;
    int height;
    int channels;  // as stored in the file: 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA
    int bitDepth;  // 8 or 16 for PNG, 8 for JPEG/TGA/BMP, 16 (half) or 32 (float) for EXR
};

// Reads the header only (no pixel allocation). Throws as described above.
ImageInfo readImageInfo(const std::filesystem::path& path);

// Reads an image with the channel count stored in the file.
Image readImage(const std::filesystem::path& path);

// What a reader of a scalar map (depth, height, AO) does with a multi-channel file.
// A gray or gray+alpha file gives its gray channel. An RGB or RGBA file gives its Rec. 709
// luminance, and a note naming the file goes to `note` (the CLI prints it on stderr).
Image readScalarMap(const std::filesystem::path& path, std::string* note = nullptr);
// The same for an image already read from `path` (for a caller that inspects the file's channels first).
Image toScalarMap(Image image, const std::filesystem::path& path, std::string* note = nullptr);

enum class PngBitDepth { Eight = 8, Sixteen = 16 };

struct PngWriteOptions {
    PngBitDepth bitDepth = PngBitDepth::Sixteen;  // CONVENTIONS §5: 16-bit unless the user asks for 8
    // 8-bit output is dithered (CONVENTIONS §5): a deterministic ordered (8x8 Bayer) dither of
    // +-0.5 LSB before rounding, so that gradients do not band. No effect at 16 bits.
    bool dither = true;
};

// Writes a 1- to 4-channel image as PNG (gray, gray+alpha, RGB, RGBA). Values are clamped to [0, 1]
// and quantised as round(v * (2^bits - 1)) (with the dither above at 8 bits). Atomic.
void writePng(const std::filesystem::path& path, const Image& image, const PngWriteOptions& options = {});

// Writes a 1- to 4-channel image as a 32-bit float, ZIP-compressed scanline OpenEXR file (channels Y, YA,
// RGB or RGBA), values as they are (no clamping). Atomic.
void writeExr(const std::filesystem::path& path, const Image& image);

// Writes an 8-bit baseline JPEG (stb_image_write, Debian's libstb) of a 1- or 3-channel image (2 and 4
// channels: the alpha is dropped), values clamped to [0, 1], quantised with the 8-bit dither above. Atomic.
void writeJpeg(const std::filesystem::path& path, const Image& image, int quality = 95);

// The format an output file's extension names (case-insensitive): .png, .exr, .jpg or .jpeg; none otherwise.
std::optional<ImageFormat> outputFormatOf(const std::filesystem::path& path);

// Checks an output file's extension before any work: returns its format if it is one of `allowed`, else
// throws Error(Usage) "<flag> <path>: cannot write .<ext>; use .png or .exr" (the allowed ones listed).
// Every command that takes `-o FILE` calls it first, so that a file named .jpg is a JPEG or an error,
// never PNG bytes under another name.
ImageFormat checkOutputExtension(const std::filesystem::path& path, const std::string& flag,
                                 std::initializer_list<ImageFormat> allowed);

// Writes PNG, EXR or JPEG, chosen by the extension (.png / .exr / .jpg, .jpeg; case-insensitive);
// any other extension throws Error(Unsupported).
void writeImage(const std::filesystem::path& path, const Image& image, const PngWriteOptions& options = {});

const char* toString(ImageFormat format);

}  // namespace strata
