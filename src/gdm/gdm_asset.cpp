#include "strata/gdm/gdm_asset.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/version.h"
#include "strata/gdm/solid_mesh_io.h"
#include "strata/image/quantize.h"

#include "core/json_reader.h"
#include "core/staging_dir.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata {

// The payloads are the host's bytes: the format says little-endian, so a big-endian host would need swaps.
static_assert(std::endian::native == std::endian::little, "GDM asset payloads are written little-endian");

namespace {

constexpr const char* kConvention = "CONVENTIONS §8";
// The solid mesh: OBJ text, not an array, so its sidecar entry is {"file", "type": "obj", "bytes"}.
constexpr const char* kSolidKey = "solid";
constexpr const char* kSolidFile = "solid.obj";

struct Payload {
    std::string key;   // the sidecar's key under "payloads"
    std::string file;  // the file name in the directory
    std::string type;  // "float32" or "uint8"
    std::vector<std::size_t> shape;
    std::size_t elementBytes = 0;
    std::size_t bytes() const {
        std::size_t n = elementBytes;
        for (std::size_t s : shape) n *= s;
        return n;
    }
};

std::vector<Payload> payloadsFor(const GdmSvd& svd, bool hasAlbedo, bool hasRaw, bool hasDistance) {
    const GdmDims& d = svd.dims;
    const auto r = std::size_t(svd.rank);
    std::vector<Payload> payloads = {
        {"weights", "weights.f32", "float32", {svd.rows, r}, 4},
        {"eigen", "eigen.f32", "float32", {r, svd.cols}, 4},
        {"occupancy", "occupancy.u8", "uint8", {std::size_t(d.nx), std::size_t(d.ny), std::size_t(d.nz)}, 1},
    };
    if (hasAlbedo)
        payloads.push_back({"albedo",
                            "albedo.rgb8",
                            "uint8",
                            {std::size_t(d.nx), std::size_t(d.ny), std::size_t(d.nz), 3},
                            1});
    if (hasRaw)
        payloads.push_back({"raw",
                            "raw.f32",
                            "float32",
                            {std::size_t(d.nx), std::size_t(d.ny), std::size_t(d.nz), std::size_t(d.ntheta),
                             std::size_t(d.nphi)},
                            4});
    if (hasDistance)
        payloads.push_back({"distance",
                            "distance.f32",
                            "float32",
                            {std::size_t(d.nx), std::size_t(d.ny), std::size_t(d.nz)},
                            4});
    return payloads;
}

std::optional<GdmLayout> layoutFromString(const std::string& name) {
    for (GdmLayout layout : {GdmLayout::XyPhiByThetaZ, GdmLayout::XyzByThetaPhi, GdmLayout::XyByZThetaPhi})
        if (name == toString(layout)) return layout;
    return std::nullopt;
}

void writeBytes(const fs::path& path, const void* data, std::size_t bytes) {
    writeFileAtomic(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
        out.close();
        if (!out)
            throw Error(ErrorKind::Io, path.string() + ": cannot write " + std::to_string(bytes) + " bytes");
    });
}

bool isEmptyDir(const fs::path& dir) {
    std::error_code ec;
    return fs::is_directory(dir, ec) && fs::directory_iterator(dir, ec) == fs::directory_iterator();
}

}  // namespace

std::vector<std::uint8_t> gdmOccupancy(const Gdm& gdm) {
    const std::size_t dirs = gdm.dims.directionCount();
    STRATA_CHECK_EQ(gdm.values.size(), gdm.dims.valueCount());
    std::vector<std::uint8_t> occupancy(gdm.dims.voxelCount(), 0);
    for (std::size_t v = 0; v < occupancy.size(); ++v) {
        bool inside = dirs > 0;
        for (std::size_t d = 0; d < dirs && inside; ++d) inside = gdm.values[v * dirs + d] == 0.0f;
        occupancy[v] = inside ? 1 : 0;
    }
    return occupancy;
}

std::vector<std::uint8_t> mesostructureAlbedo(const Mesostructure& meso, const GdmDims& dims) {
    std::vector<std::uint8_t> albedo(dims.voxelCount() * 3);
    std::size_t at = 0;
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                const glm::dvec3 colour = meso.sample(gdmVoxelCentre(dims, meso.height(), i, j, k)).albedo;
                for (int c = 0; c < 3; ++c) albedo[at++] = toUnorm8(colour[c]);
            }
    return albedo;
}

void writeGdmAsset(const fs::path& dir, const GdmAsset& asset, const std::vector<fs::path>& inputs) {
    const GdmSvd& svd = asset.svd;
    const std::string what = dir.string();
    validateGdmDims(svd.dims, svd.height, what, std::numeric_limits<std::size_t>::max());
    if (svd.rank < 1 || svd.rows != gdmLayoutRows(svd.dims, svd.layout) ||
        svd.cols != gdmLayoutCols(svd.dims, svd.layout) ||
        svd.weights.size() != svd.rows * std::size_t(svd.rank) ||
        svd.eigen.size() != std::size_t(svd.rank) * svd.cols ||
        svd.singularValues.size() != std::size_t(svd.rank))
        throw Error(ErrorKind::InvalidInput, what + ": the GDM's SVD maps do not match its dims and rank");
    if (asset.occupancy.size() != svd.dims.voxelCount())
        throw Error(ErrorKind::InvalidInput, what + ": the occupancy volume has " +
                                                 std::to_string(asset.occupancy.size()) + " voxels, not " +
                                                 std::to_string(svd.dims.voxelCount()));
    if (!asset.albedo.empty() && asset.albedo.size() != svd.dims.voxelCount() * 3)
        throw Error(ErrorKind::InvalidInput, what + ": the albedo volume has " +
                                                 std::to_string(asset.albedo.size()) +
                                                 " bytes, not 3 per voxel");
    if (asset.raw && (asset.raw->dims != svd.dims || asset.raw->height != svd.height ||
                      asset.raw->values.size() != svd.dims.valueCount()))
        throw Error(ErrorKind::InvalidInput, what + ": the raw GDM's dims or H differ from the SVD's");
    if (!asset.distance.empty() && asset.distance.size() != svd.dims.voxelCount())
        throw Error(ErrorKind::InvalidInput, what + ": the distance volume has " +
                                                 std::to_string(asset.distance.size()) + " voxels, not " +
                                                 std::to_string(svd.dims.voxelCount()));
    for (const float value : asset.distance)
        if (!std::isfinite(value))
            throw Error(ErrorKind::InvalidInput, what + ": the distance volume holds a value " +
                                                     formatNumber(value) + " that is not finite");
    std::string solidText;
    if (asset.solid) {
        if (asset.solid->height != svd.height)
            throw Error(ErrorKind::InvalidInput, what + ": the solid's H " +
                                                     formatNumber(asset.solid->height) +
                                                     " differs from the SVD's " + formatNumber(svd.height));
        // What could not be read back is not written.
        validateSolidMesh(*asset.solid, what + ": the solid");
        solidText = solidObjText(*asset.solid);
    }

    std::error_code ec;
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir, ec)) throw Error(ErrorKind::Io, what + ": exists and is not a directory");
        if (!isEmptyDir(dir) && !isGdmAsset(dir))
            throw Error(ErrorKind::Io, what + ": exists and is not a GDM asset (refusing to overwrite it)");
    }
    for (const fs::path& input : inputs)
        if (fs::equivalent(dir, input, ec))
            throw Error(ErrorKind::Io, what + ": is an input (refusing to overwrite it)");

    const std::vector<Payload> payloads =
        payloadsFor(svd, !asset.albedo.empty(), asset.raw.has_value(), !asset.distance.empty());
    json sidecar;
    sidecar["format"] = kGdmAssetFormat;
    sidecar["version"] = kGdmAssetVersion;
    sidecar["tool"] = std::string("strata ") + kVersion;
    sidecar["convention"] = kConvention;
    sidecar["dims"] = {{"nx", svd.dims.nx},
                       {"ny", svd.dims.ny},
                       {"nz", svd.dims.nz},
                       {"ntheta", svd.dims.ntheta},
                       {"nphi", svd.dims.nphi}};
    sidecar["height"] = svd.height;
    sidecar["rank"] = svd.rank;
    sidecar["layout"] = toString(svd.layout);
    sidecar["rows"] = svd.rows;
    sidecar["cols"] = svd.cols;
    sidecar["exit_tolerance"] = svd.exitTolerance;
    sidecar["singular_values"] = svd.singularValues;
    sidecar["source"] = asset.source;
    sidecar["bake"] = {
        {"settings", asset.bake.settings}, {"seconds", asset.bake.seconds}, {"date", asset.bake.date}};
    json files = json::object();
    for (const Payload& p : payloads)
        files[p.key] = {{"file", p.file},
                        {"type", p.type},
                        {"endian", "little"},
                        {"shape", p.shape},
                        {"bytes", p.bytes()}};
    if (asset.solid) files[kSolidKey] = {{"file", kSolidFile}, {"type", "obj"}, {"bytes", solidText.size()}};
    sidecar["payloads"] = files;

    detail::StagingDir staging(dir);
    std::vector<std::string> names;
    for (const Payload& p : payloads) {
        refuseToOverwriteInputs(dir / p.file, inputs);
        const void* data = p.key == "weights"    ? static_cast<const void*>(svd.weights.data())
                           : p.key == "eigen"    ? static_cast<const void*>(svd.eigen.data())
                           : p.key == "raw"      ? static_cast<const void*>(asset.raw->values.data())
                           : p.key == "albedo"   ? static_cast<const void*>(asset.albedo.data())
                           : p.key == "distance" ? static_cast<const void*>(asset.distance.data())
                                                 : static_cast<const void*>(asset.occupancy.data());
        writeBytes(staging.path() / p.file, data, p.bytes());
        names.push_back(p.file);
    }
    if (asset.solid) {
        refuseToOverwriteInputs(dir / kSolidFile, inputs);
        writeTextFileAtomic(staging.path() / kSolidFile, solidText);
        names.emplace_back(kSolidFile);
    }
    refuseToOverwriteInputs(dir / kGdmAssetSidecar, inputs);
    writeTextFileAtomic(staging.path() / kGdmAssetSidecar, sidecar.dump(2) + "\n");
    names.emplace_back(kGdmAssetSidecar);

    // An older asset's sidecar goes first, so that a failure half-way never leaves a sidecar naming
    // payloads of another bake; the new one moves in last.
    staging.moveInto(dir, names, [&] {
        fs::remove(dir / kGdmAssetSidecar, ec);
        if (!asset.raw) fs::remove(dir / "raw.f32", ec);
        if (asset.albedo.empty()) fs::remove(dir / "albedo.rgb8", ec);
        if (asset.distance.empty()) fs::remove(dir / "distance.f32", ec);
        if (!asset.solid) fs::remove(dir / kSolidFile, ec);
    });
}

bool isGdmAsset(const fs::path& dir) {
    try {
        std::error_code ec;
        if (!fs::is_regular_file(dir / kGdmAssetSidecar, ec)) return false;
        const json sidecar = json::parse(readTextFile(dir / kGdmAssetSidecar));
        return sidecar.is_object() && sidecar.value("format", "") == kGdmAssetFormat;
    } catch (...) {
        return false;
    }
}

GdmAsset readGdmAsset(const fs::path& dir) {
    const fs::path sidecarPath = dir / kGdmAssetSidecar;
    const std::string file = sidecarPath.string();
    const json sidecar = detail::readJsonFile(sidecarPath);
    detail::JsonObjectReader top(sidecar, "", file);
    auto required = [&](auto value, const std::string& key) {
        if (!value) top.fail(key, "missing");
        return *value;
    };
    if (required(top.string("format"), "format") != kGdmAssetFormat)
        top.fail("format", std::string("must be \"") + kGdmAssetFormat + "\" (not a GDM asset)");
    const long long version = required(top.integer("version", 0, 1 << 30), "version");
    if (version != kGdmAssetVersion)
        top.fail("version", "unknown version " + std::to_string(version) + " (this strata reads " +
                                std::to_string(kGdmAssetVersion) + ")");
    top.string("tool");
    const std::string convention = required(top.string("convention"), "convention");
    if (convention != kConvention) top.fail("convention", "must be \"" + std::string(kConvention) + "\"");

    GdmAsset asset;
    GdmSvd& svd = asset.svd;
    const json* dimsJson = top.object("dims");
    if (!dimsJson) top.fail("dims", "missing");
    detail::JsonObjectReader dims(*dimsJson, "dims", file);
    auto dim = [&](const char* key) {
        const auto v = dims.integer(key, 1, 1 << 20);
        if (!v) dims.fail(dims.keyPath(key), "missing");
        return int(*v);
    };
    svd.dims = {dim("nx"), dim("ny"), dim("nz"), dim("ntheta"), dim("nphi")};
    dims.rejectUnknown();
    svd.height = required(top.number("height"), "height");
    if (!(svd.height > 0.0)) top.fail("height", "must be > 0");
    validateGdmDims(svd.dims, svd.height, file, std::numeric_limits<std::size_t>::max());
    const std::string layoutName = required(top.string("layout"), "layout");
    const auto layout = layoutFromString(layoutName);
    if (!layout) top.fail("layout", "unknown layout \"" + layoutName + "\"");
    svd.layout = *layout;
    svd.rows = gdmLayoutRows(svd.dims, svd.layout);
    svd.cols = gdmLayoutCols(svd.dims, svd.layout);
    svd.rank =
        int(required(top.integer("rank", 1, static_cast<long long>(std::min(svd.rows, svd.cols))), "rank"));
    if (std::size_t(required(top.integer("rows", 0, 1LL << 62), "rows")) != svd.rows)
        top.fail("rows", "must be " + std::to_string(svd.rows) + " for these dims and layout");
    if (std::size_t(required(top.integer("cols", 0, 1LL << 62), "cols")) != svd.cols)
        top.fail("cols", "must be " + std::to_string(svd.cols) + " for these dims and layout");
    svd.exitTolerance = required(top.number("exit_tolerance"), "exit_tolerance");
    if (svd.exitTolerance < 0.0) top.fail("exit_tolerance", "must be >= 0");
    const json* sigma = top.array("singular_values");
    if (!sigma) top.fail("singular_values", "missing");
    if (sigma->size() != std::size_t(svd.rank))
        top.fail("singular_values", "must hold rank = " + std::to_string(svd.rank) + " numbers");
    for (const json& s : *sigma) {
        if (!s.is_number()) top.fail("singular_values", "must hold numbers");
        svd.singularValues.push_back(s.get<double>());
    }
    asset.source = required(top.string("source"), "source");
    const json* bakeJson = top.object("bake");
    if (!bakeJson) top.fail("bake", "missing");
    detail::JsonObjectReader bake(*bakeJson, "bake", file);
    asset.bake.settings = bake.string("settings").value_or("");
    asset.bake.seconds = bake.number("seconds").value_or(0.0);
    asset.bake.date = bake.string("date").value_or("");
    bake.rejectUnknown();

    const json* filesJson = top.object("payloads");
    if (!filesJson) top.fail("payloads", "missing");
    top.rejectUnknown();
    detail::JsonObjectReader files(*filesJson, "payloads", file);
    const bool hasRaw = files.has("raw");
    for (const Payload& p : payloadsFor(svd, files.has("albedo"), hasRaw, files.has("distance"))) {
        const json* entry = files.object(p.key);
        const std::string where = "payloads." + p.key;
        if (!entry) files.fail(where, "missing");
        detail::JsonObjectReader e(*entry, where, file);
        if (e.string("file") != p.file) e.fail(where + ".file", "must be \"" + p.file + "\"");
        if (e.string("type") != p.type) e.fail(where + ".type", "must be \"" + p.type + "\"");
        if (e.string("endian") != "little") e.fail(where + ".endian", "must be \"little\"");
        if (e.integer("bytes", 0, 1LL << 62) != static_cast<long long>(p.bytes()))
            e.fail(where + ".bytes", "must be " + std::to_string(p.bytes()) + " for the dims and rank");
        const json* shape = e.array("shape");
        if (!shape || *shape != json(p.shape)) e.fail(where + ".shape", "must be " + json(p.shape).dump());
        e.rejectUnknown();

        const fs::path path = dir / p.file;
        const std::vector<unsigned char> bytes = readFileBytes(path);
        if (bytes.size() != p.bytes())
            throw Error(ErrorKind::InvalidInput,
                        path.string() + ": " + std::to_string(bytes.size()) + " bytes, the sidecar's " +
                            where + " needs " + std::to_string(p.bytes()) + " (truncated or wrong file)");
        auto floats = [&] {
            std::vector<float> v(bytes.size() / 4);
            if (!bytes.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
            for (float x : v)
                if (std::isnan(x) || (p.key != "raw" && !std::isfinite(x)) || (p.key == "raw" && x < 0.0f))
                    throw Error(ErrorKind::InvalidInput, path.string() + ": holds a value " +
                                                             formatNumber(x) + " that " + where +
                                                             " cannot hold");
            return v;
        };
        if (p.key == "weights") svd.weights = floats();
        if (p.key == "eigen") svd.eigen = floats();
        if (p.key == "raw") asset.raw = Gdm{svd.dims, svd.height, floats()};
        if (p.key == "albedo") asset.albedo.assign(bytes.begin(), bytes.end());
        if (p.key == "distance") asset.distance = floats();
        if (p.key == "occupancy") {
            asset.occupancy.assign(bytes.begin(), bytes.end());
            for (std::uint8_t o : asset.occupancy)
                if (o > 1)
                    throw Error(ErrorKind::InvalidInput, path.string() + ": occupancy values must be 0 or 1");
        }
    }
    if (const json* entry = files.object(kSolidKey)) {
        const std::string where = std::string("payloads.") + kSolidKey;
        detail::JsonObjectReader e(*entry, where, file);
        if (e.string("file") != kSolidFile)
            e.fail(where + ".file", std::string("must be \"") + kSolidFile + "\"");
        if (e.string("type") != "obj") e.fail(where + ".type", "must be \"obj\"");
        const auto bytes = e.integer("bytes", 1, 1LL << 62);
        if (!bytes) e.fail(where + ".bytes", "missing (an integer >= 1)");
        e.rejectUnknown();
        const fs::path path = dir / kSolidFile;
        const std::string text = readTextFile(path);
        if (static_cast<long long>(text.size()) != *bytes)
            throw Error(ErrorKind::InvalidInput, path.string() + ": " + std::to_string(text.size()) +
                                                     " bytes, the sidecar's " + where + " says " +
                                                     std::to_string(*bytes) + " (truncated or wrong file)");
        asset.solid = parseSolidObj(text, path.string(), svd.height);
        asset.solid->source = asset.source;
    }
    files.rejectUnknown();
    return asset;
}

}  // namespace strata
