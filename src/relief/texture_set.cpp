#include "strata/relief/texture_set.h"

#include "strata/relief/import.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/version.h"
#include "strata/image/image_io.h"
#include "strata/image/image_ops.h"

#include "core/json_reader.h"
#include "core/staging_dir.h"

#include <nlohmann/json.hpp>

#include <unistd.h>
#include <atomic>
#include <cmath>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata {

namespace {

json sizeOf(const Image& image) {
    return json::array({image.width(), image.height()});
}

// Normals at another resolution: resample each component and renormalise.
Image resampleNormals(const Image& normals, int width, int height) {
    Image out = resample(normals, width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float* n = &out.at(x, y);
            const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (length > 0.0f)
                for (int c = 0; c < 3; ++c) n[c] /= length;
        }
    return out;
}

// How one data map is written: a PNG of the set's bit depth, or a float EXR.
struct MapWriter {
    MapFileFormat format;
    PngWriteOptions png;
    std::string name(const std::string& stem) const { return stem + "." + toString(format); }
    void write(const fs::path& path, const Image& image) const {
        if (format == MapFileFormat::Exr)
            writeExr(path, image);
        else
            writePng(path, image, png);
    }
};

constexpr const char* kPackedLayout =
    "R = nx * 0.5 + 0.5, G = ny * 0.5 + 0.5, B = AO, A = depth; nz = sqrt(1 - nx^2 - ny^2)";

}  // namespace

const char* toString(MapFileFormat format) {
    return format == MapFileFormat::Exr ? "exr" : "png";
}

MapFileFormat parseMapFileFormat(const std::string& text, const std::string& flag) {
    if (text == "png") return MapFileFormat::Png;
    if (text == "exr") return MapFileFormat::Exr;
    throw Error(ErrorKind::Usage, flag + ": must be png or exr, got '" + text + "'");
}

Image packRelief(const ReliefTexture& texture) {
    const int width = texture.depth.width();
    const int height = texture.depth.height();
    const Image normals = texture.normal.width() == width && texture.normal.height() == height
                              ? texture.normal
                              : resampleNormals(texture.normal, width, height);
    const bool hasAo = !texture.ao.empty();
    const Image ao = !hasAo || (texture.ao.width() == width && texture.ao.height() == height)
                         ? texture.ao
                         : resample(texture.ao, width, height);
    Image packed(width, height, 4);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            packed.at(x, y, 0) = normals.at(x, y, 0) * 0.5f + 0.5f;
            packed.at(x, y, 1) = normals.at(x, y, 1) * 0.5f + 0.5f;
            packed.at(x, y, 2) = hasAo ? ao.at(x, y) : 1.0f;
            packed.at(x, y, 3) = texture.depth.at(x, y);
        }
    return packed;
}

std::vector<fs::path> writeTextureSet(const fs::path& dir, const ReliefTexture& texture,
                                      const TextureSetWriteOptions& options) {
    if (options.bitDepth != 8 && options.bitDepth != 16)
        throw Error(ErrorKind::InvalidInput,
                    "bit depth must be 8 or 16, got " + std::to_string(options.bitDepth));
    if (texture.depth.empty() || texture.normal.empty())
        throw Error(ErrorKind::InvalidInput, dir.string() + ": a texture set needs depth and normal maps");
    if (!texture.ao.empty() && !options.ao)
        throw Error(ErrorKind::InvalidInput,
                    dir.string() + ": the AO map needs its record (radius, definition)");

    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw Error(ErrorKind::Io, dir.string() + ": exists and is not a directory");

    const MapWriter data{options.format,
                         {options.bitDepth == 8 ? PngBitDepth::Eight : PngBitDepth::Sixteen, true}};
    const PngWriteOptions colour{PngBitDepth::Eight, true};
    const bool exr = options.format == MapFileFormat::Exr;

    json sidecar;
    sidecar["format"] = kSidecarFormat;
    sidecar["format_version"] = 1;
    sidecar["tool"] = std::string("strata ") + kVersion;
    sidecar["depth_scale"] = texture.depthScale;
    // EXR maps are 32-bit float whatever --bit-depth says (the colour map is always 8-bit sRGB).
    sidecar["file_format"] = toString(options.format);
    sidecar["bit_depth"] = exr ? 32 : options.bitDepth;
    sidecar["texture_space"] =
        "u along +x (tangent), v along +y (bitangent); file row 0 is v = 1; tiles toroidally";
    sidecar["depth"] = {{"file", data.name("depth")},
                        {"encoding", "depth"},
                        {"meaning", "0 = polygon surface (top), 1 = deepest; relief point (u, v, -S * d)"},
                        {"size", sizeOf(texture.depth)}};
    if (options.height)
        sidecar["height"] = {{"file", data.name("height")},
                             {"encoding", "height"},
                             {"meaning", "h = 1 - depth: 1 = polygon surface (top, white), 0 = deepest"},
                             {"amplitude", texture.depthScale},
                             {"amplitude_meaning", "h = 0 lies S tile widths below h = 1 (S = depth_scale)"},
                             {"size", sizeOf(texture.depth)}};
    sidecar["normal"] = {{"file", data.name("normal")},      {"convention", "opengl"},
                         {"green", "up (+y towards v = 1)"}, {"encoding", "n * 0.5 + 0.5"},
                         {"source", options.normalSource},   {"valid_for_depth_scale", texture.depthScale},
                         {"size", sizeOf(texture.normal)}};
    sidecar["color"] = texture.color.empty() ? json(nullptr)
                                             : json{{"file", "color.png"},
                                                    {"encoding", "sRGB"},
                                                    {"bit_depth", 8},
                                                    {"size", sizeOf(texture.color)}};
    if (texture.ao.empty()) {
        sidecar["ao"] = nullptr;
    } else {
        sidecar["ao"] = {{"file", data.name("ao")},
                         {"radius", options.ao->radius},
                         {"definition", options.ao->definition},
                         {"method", options.ao->method},
                         {"directions", options.ao->directions},
                         {"baked_at_depth_scale", texture.depthScale},
                         {"size", sizeOf(texture.ao)}};
    }
    sidecar["packed"] = {{"file", data.name("packed")},
                         {"layout", kPackedLayout},
                         {"ao_channel", texture.ao.empty() ? "no AO map: 1.0 (fully open)" : data.name("ao")},
                         {"size", sizeOf(texture.depth)}};
    try {
        sidecar["source"] = json::parse(options.sourceJson);
    } catch (const json::exception&) {
        sidecar["source"] = options.sourceJson;
    }

    // Everything is written into the staging directory first, so any failure leaves `dir` untouched
    // (and uncreated, if it did not exist).
    std::vector<std::string> names;
    detail::StagingDir staging(dir);
    auto stage = [&](const std::string& name, auto write) {
        refuseToOverwriteInputs(dir / name, options.inputs);
        write(staging.path() / name);
        names.push_back(name);
    };
    auto stageData = [&](const std::string& stem, const Image& image) {
        stage(data.name(stem), [&](const fs::path& path) { data.write(path, image); });
    };
    stageData("depth", texture.depth);
    if (options.height) stageData("height", heightToDepth(texture.depth));  // the same map both ways
    stageData("normal", encodeNormals(texture.normal));
    if (!texture.color.empty())
        stage("color.png", [&](const fs::path& path) { writePng(path, texture.color, colour); });
    if (!texture.ao.empty()) stageData("ao", texture.ao);
    stageData("packed", packRelief(texture));
    refuseToOverwriteInputs(dir / kSidecarName, options.inputs);
    writeTextFileAtomic(staging.path() / kSidecarName, sidecar.dump(2) + "\n");
    names.emplace_back(kSidecarName);

    // The sidecar moves in last: it is what says which maps belong to the set, so files in `dir`
    // that this set does not name (an older colour map, a user's own file) are left alone.
    return staging.moveInto(dir, names);
}

json readSidecar(const fs::path& path) {
    std::error_code ec;
    const bool isDirectory = fs::is_directory(path, ec);
    const fs::path file = isDirectory ? path / kSidecarName : path;
    if (isDirectory && !fs::exists(file, ec))
        throw Error(ErrorKind::Io, path.string() + ": not a texture set (it has no " + kSidecarName + ")");
    const json sidecar = detail::parseJsonStrict(readTextFile(file), file.string());
    if (!sidecar.is_object() || sidecar.value("format", "") != kSidecarFormat)
        throw Error(ErrorKind::InvalidInput, file.string() +
                                                 ": not a Strata texture-set sidecar (\"format\" is not \"" +
                                                 kSidecarFormat + "\")");
    // Every command takes depth scales in (0, 10] (kMaxReliefDepthScale): a set outside is named here, not
    // refused later by another command.
    const auto scale = sidecar.find("depth_scale");
    if (scale != sidecar.end() && scale->is_number() &&
        !(scale->get<double>() > 0.0 && scale->get<double>() <= kMaxReliefDepthScale))
        throw Error(ErrorKind::InvalidInput, file.string() + ": \"depth_scale\" must be in (0, 10], got " +
                                                 formatNumber(scale->get<double>()));
    return sidecar;
}

Image readDepthMap(const fs::path& path, DepthEncoding encoding, std::string* note) {
    // Read once to check that an RGB file is not a normal map given as height or depth.
    Image image = readImage(path);
    if (image.channels() >= 3) checkDepthMapContent(image, path.string());
    Image map = toScalarMap(std::move(image), path, note);
    if (encoding == DepthEncoding::Height) return heightToDepth(map);
    return map;  // moved, not copied: a 16384^2 depth map is 1 GiB
}

Image readNormalMap(const fs::path& path, bool flipY) {
    const Image encoded = readImage(path);
    if (encoded.channels() < 3)
        throw Error(ErrorKind::InvalidInput, path.string() +
                                                 ": a normal map needs 3 channels (RGB), it has " +
                                                 std::to_string(encoded.channels()));
    checkNormalMapContent(encoded, path.string());
    return decodeNormals(encoded, flipY);
}

ReliefTexture readTextureSet(const fs::path& path) {
    const fs::path dir = fs::is_directory(path) ? path : path.parent_path();
    const json sidecar = readSidecar(path);
    const fs::path sidecarPath = dir / kSidecarName;
    auto fileOf = [&](const char* key) -> std::optional<fs::path> {
        const auto it = sidecar.find(key);
        if (it == sidecar.end() || it->is_null()) return std::nullopt;
        if (!it->is_object() || !it->contains("file") || !(*it)["file"].is_string())
            throw Error(ErrorKind::InvalidInput,
                        sidecarPath.string() + ": \"" + key + "\" has no \"file\" string");
        return dir / (*it)["file"].get<std::string>();
    };
    ReliefTexture texture;
    try {
        texture.depthScale = sidecar.at("depth_scale").get<double>();
    } catch (const json::exception&) {
        throw Error(ErrorKind::InvalidInput,
                    sidecarPath.string() + ": \"depth_scale\" is missing or not a number");
    }
    const auto depthFile = fileOf("depth");
    const auto normalFile = fileOf("normal");
    if (!depthFile || !normalFile)
        throw Error(ErrorKind::InvalidInput,
                    sidecarPath.string() + ": a texture set needs \"depth\" and \"normal\"");
    texture.depth = readDepthMap(*depthFile, DepthEncoding::Depth);
    texture.normal = readNormalMap(*normalFile);
    // A set's normal map is OpenGL (import converts); one clearly the other way is refused here, so
    // compose and render check sets the same way as import and materials do.
    resolveNormalY(texture.normal, texture.depth, NormalY::Up, false, normalFile->string(),
                   "re-import it with --normal-y down or auto");
    if (const auto colorFile = fileOf("color")) {
        texture.color = toRgb(readImage(*colorFile));
    }
    if (const auto aoFile = fileOf("ao")) texture.ao = readScalarMap(*aoFile);
    return texture;
}

std::vector<fs::path> writeTextureSetAo(const fs::path& dir, const Image& ao, const AoRecord& record) {
    json sidecar = readSidecar(dir);
    const ReliefTexture texture = readTextureSet(dir);
    if (ao.channels() != 1 || ao.width() != texture.depth.width() || ao.height() != texture.depth.height())
        throw Error(ErrorKind::InvalidInput,
                    dir.string() + ": the AO map is " + std::to_string(ao.width()) + "x" +
                        std::to_string(ao.height()) + ", the set's depth map " +
                        std::to_string(texture.depth.width()) + "x" + std::to_string(texture.depth.height()));
    const int bitDepth = sidecar.value("bit_depth", 16) == 8 ? 8 : 16;
    const auto fileFormat = sidecar.find("file_format");
    const MapFileFormat format =
        fileFormat != sidecar.end() && fileFormat->is_string() && *fileFormat == "exr" ? MapFileFormat::Exr
                                                                                       : MapFileFormat::Png;
    const MapWriter data{format, {bitDepth == 8 ? PngBitDepth::Eight : PngBitDepth::Sixteen, true}};
    // The packed map as stored (when it is there and the right size), only B replaced.
    Image packed;
    const auto packedEntry = sidecar.find("packed");
    if (packedEntry != sidecar.end() && packedEntry->is_object() && packedEntry->contains("file") &&
        (*packedEntry)["file"].is_string()) {
        const fs::path packedFile = dir / (*packedEntry)["file"].get<std::string>();
        std::error_code ec;
        if (fs::exists(packedFile, ec)) packed = readImage(packedFile);
    }
    if (packed.channels() != 4 || packed.width() != ao.width() || packed.height() != ao.height())
        packed = packRelief(texture);
    for (int y = 0; y < ao.height(); ++y)
        for (int x = 0; x < ao.width(); ++x) packed.at(x, y, 2) = ao.at(x, y);

    const std::string aoName = data.name("ao");
    const std::string packedName = data.name("packed");
    sidecar["ao"] = {{"file", aoName},
                     {"radius", record.radius},
                     {"definition", record.definition},
                     {"method", record.method},
                     {"directions", record.directions},
                     {"baked_at_depth_scale", texture.depthScale},
                     {"size", sizeOf(ao)}};
    sidecar["packed"] = {{"file", packedName},
                         {"layout", kPackedLayout},
                         {"ao_channel", aoName},
                         {"size", sizeOf(texture.depth)}};

    detail::StagingDir staging(dir);
    data.write(staging.path() / aoName, ao);
    data.write(staging.path() / packedName, packed);
    writeTextFileAtomic(staging.path() / kSidecarName, sidecar.dump(2) + "\n");
    return staging.moveInto(dir, {aoName, packedName, kSidecarName});
}

}  // namespace strata
