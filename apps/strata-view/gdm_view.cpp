#include "gdm_view.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gl/gdm_picture.h"

#include <chrono>
#include <cstdio>

namespace strata::view {

bool sameFrame(const GdmFrame& a, const GdmFrame& b) {
    return a.settings == b.settings && a.camera.eye == b.camera.eye && a.camera.target == b.camera.target &&
           a.camera.up == b.camera.up && a.camera.fovYDegrees == b.camera.fovYDegrees &&
           a.lighting.lightPosition == b.lighting.lightPosition &&
           a.lighting.lightColor == b.lighting.lightColor && a.lighting.ambient == b.lighting.ambient &&
           a.lighting.specular == b.lighting.specular && a.lighting.shininess == b.lighting.shininess &&
           a.width == b.width && a.height == b.height && a.samples == b.samples &&
           a.background == b.background && a.mesh == b.mesh;
}

PictureSettings gdmPictureSettings(const GdmFrame& frame) {
    PictureSettings picture;
    picture.width = frame.width;
    picture.height = frame.height;
    picture.samples = frame.samples;
    picture.output = RenderOutput::Shaded;
    picture.background = frame.background;
    return picture;
}

namespace {

PrismShellOptions shellOptions(const SceneGdm& gdm, const GdmViewSettings& settings) {
    PrismShellOptions options;
    options.height = gdm.asset.svd.height;
    options.tiling = glm::dvec2(settings.tiling);
    options.thickness = settings.shellThickness;
    return options;
}

double mebibytes(std::size_t bytes) {
    return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

}  // namespace

PrismShell gdmShell(const SceneGdm& gdm, const Mesh& mesh, const GdmViewSettings& settings) {
    return buildPrismShell(mesh, shellOptions(gdm, settings));
}

Bounds gdmFramingBounds(const Mesh& mesh, double thickness) {
    Bounds bounds = meshBounds(mesh);
    const auto grow = glm::vec3(static_cast<float>(thickness));
    bounds.min -= grow;
    bounds.max += grow;
    return bounds;
}

GdmDescription describeGdm(const SceneGdm& gdm) {
    const GdmAsset& asset = gdm.asset;
    GdmDescription out;
    // loadSceneGdm's description ends with the rank it picked (and then, with an environment, the
    // environment and its RTV's rank and bounces); the panel shows each of those itself.
    std::string description = gdm.description;
    if (hasEnvironment(gdm)) {
        const std::size_t environment = description.rfind(", " + gdm.environmentName + " (RTV");
        if (environment != std::string::npos) description.resize(environment);
    }
    out.source = description.substr(0, description.rfind(", "));
    const GdmDims& d = asset.svd.dims;
    char dims[160];
    std::snprintf(dims, sizeof(dims), "%d x %d x %d voxels, %d x %d directions", d.nx, d.ny, d.nz, d.ntheta,
                  d.nphi);
    out.dims = dims;
    out.height = asset.svd.height;
    out.storedRank = asset.svd.rank;
    out.hasRaw = asset.raw.has_value();
    out.svdMiB = mebibytes(asset.svd.mapBytes());
    out.rawMiB = asset.raw ? mebibytes(asset.raw->values.size() * sizeof(float)) : 0.0;
    out.volumeMiB = mebibytes(asset.occupancy.size() + asset.albedo.size());
    if (hasEnvironment(gdm)) {
        out.environment = gdm.environmentName;
        out.rtvRank = gdm.rtv->rank;
        out.rtvMiB = mebibytes((gdm.rtv->weights.size() + gdm.rtv->basis.size()) * sizeof(float));
    }
    return out;
}

bool hasEnvironment(const SceneGdm& gdm) {
    return gdm.rtv.has_value() && gdm.environment.has_value();
}

// --- GdmView --------------------------------------------------------------------------------------------

GdmView::GdmView(std::shared_ptr<const SceneGdm> gdm) : mGdm(std::move(gdm)) {}

GdmView::~GdmView() = default;

void GdmView::setMesh(std::shared_ptr<const Mesh> mesh, std::uint64_t id) {
    mMesh = std::move(mesh);
    mMeshId = id;
}

Image GdmView::render(const GdmFrame& frame) {
    const GdmViewSettings& settings = frame.settings;
    const GdmAsset& asset = mGdm->asset;
    if (!mMesh || frame.mesh != mMeshId)
        throw Error(ErrorKind::InvalidInput,
                    "GDM view: the frame's mesh " + std::to_string(frame.mesh) + " was not set (setMesh)");
    try {
        const bool environment = hasEnvironment(*mGdm);
        const int rank = settings.rank == 0 ? asset.svd.rank : settings.rank;
        if (mUploadedRank != rank) {
            mUploadedRank.reset();
            // setGdm forgets the shell, the volumes and the RTV (and with the shell the macro transfer and
            // the environment).
            mUploadedShell.reset();
            mUploadedRtv = false;
            if (rank == kGdmRankRaw) {
                if (!asset.raw)
                    throw Error(ErrorKind::InvalidInput,
                                mGdm->description + ": rank raw: the asset holds no raw GDM (raw.f32)");
                mRenderer.setGdm(*asset.raw);
            } else if (rank == asset.svd.rank) {
                mRenderer.setGdm(asset.svd);
            } else {
                // The first `rank` terms of the stored SVD (throws for a rank < 1 or above the stored one).
                mRenderer.setGdm(truncateGdmSvd(asset.svd, rank));
            }
            ++mGdmUploads;
            mUploadedRank = rank;
        }
        const auto shell = std::make_tuple(mMeshId, settings.tiling, settings.shellThickness);
        if (mUploadedShell != shell) {
            mUploadedShell.reset();
            // setMesh forgets the macro transfer and the environment.
            mUploadedMacroTransfer = false;
            mUploadedEnvironment.reset();
            const PrismShellOptions options = shellOptions(*mGdm, settings);
            mRenderer.setMesh(*mMesh, options);
            mRenderer.setVolumes(asset.occupancy, asset.albedo);
            if (!asset.distance.empty()) mRenderer.setDistance(asset.distance);
            ++mShellBuilds;
            mUploadedShell = shell;
            if (environment) {
                // The macro transfer gathers the lighting at the top of the shell: it depends on the mesh
                // and T alone (prepareGdmRenderer's bake), so a tiling that leaves T as it was keeps it.
                const double thickness = buildPrismShell(*mMesh, options).thickness;
                const auto key = std::make_pair(mMeshId, thickness);
                if (mMacroTransferKey != key) {
                    mMacroTransferKey.reset();
                    MacroTransferOptions macro;
                    macro.shellThickness = thickness;
                    mMacroTransfer = bakeMacroTransfer(*mMesh, macro);
                    ++mMacroTransferBakes;
                    mMacroTransferKey = key;
                }
            }
        }
        if (environment) {
            if (!mUploadedRtv) {
                mRenderer.setRtv(*mGdm->rtv);
                if (mGdm->glossy) mRenderer.setGlossyRtv(*mGdm->glossy, mGdm->glossySpecular);
                ++mRtvUploads;
                mUploadedRtv = true;
            }
            if (!mUploadedMacroTransfer) {
                mRenderer.setMacroTransfer(mMacroTransfer);
                ++mMacroTransferUploads;
                mUploadedMacroTransfer = true;
                mUploadedEnvironment.reset();  // setMacroTransfer forgets the environment
            }
            const auto turn = std::make_pair(settings.environmentRotation, settings.environmentIntensity);
            if (mUploadedEnvironment != turn) {
                mUploadedEnvironment.reset();
                mRenderer.setEnvironment(turnEnvironment(mGdm->environmentSh, turn.first, turn.second));
                ++mEnvironmentUploads;
                mUploadedEnvironment = turn;
            }
        }
        mRenderer.setLightFrame(settings.lightFrame);
        mRenderer.setLighting(frame.lighting);
        Image picture = gl::renderGdmPicture(mRenderer, frame.camera, frame.lighting,
                                             gdmPictureSettings(frame), settings.technique);
        ++mRenders;
        return picture;
    } catch (...) {
        // What the renderer holds is unknown after a failure part way: upload everything next time.
        mUploadedRank.reset();
        mUploadedShell.reset();
        mUploadedRtv = false;
        mUploadedMacroTransfer = false;
        mUploadedEnvironment.reset();
        throw;
    }
}

// --- GdmWorker ------------------------------------------------------------------------------------------

GdmWorker::GdmWorker(std::shared_ptr<const SceneGdm> gdm, std::function<void()> makeCurrent,
                     std::function<void()> release)
    : mThread(&GdmWorker::loop, this, std::move(gdm), std::move(makeCurrent), std::move(release)) {}

GdmWorker::~GdmWorker() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    mThread.join();
}

std::uint64_t GdmWorker::submit(const GdmFrame& frame, std::shared_ptr<const Mesh> mesh) {
    std::uint64_t number = 0;
    {
        std::lock_guard lock(mMutex);
        number = ++mSubmitted;
        mPending = Job{number, frame, std::move(mesh)};
    }
    mWake.notify_all();
    return number;
}

std::optional<GdmPicture> GdmWorker::take() {
    std::lock_guard lock(mMutex);
    std::optional<GdmPicture> out = std::move(mResult);
    mResult.reset();
    return out;
}

GdmPicture GdmWorker::wait(std::uint64_t job) {
    std::unique_lock lock(mMutex);
    mDone.wait(lock, [&] { return mFinished >= job && mResult; });
    GdmPicture out = std::move(*mResult);
    mResult.reset();
    return out;
}

bool GdmWorker::busy() const {
    std::lock_guard lock(mMutex);
    return mRunning || mPending.has_value();
}

void GdmWorker::loop(std::shared_ptr<const SceneGdm> gdm, std::function<void()> makeCurrent,
                     std::function<void()> release) {
    std::unique_ptr<GdmView> view;
    std::exception_ptr startFailure;
    bool current = false;
    try {
        makeCurrent();
        current = true;
        view = std::make_unique<GdmView>(std::move(gdm));
    } catch (...) {
        startFailure = std::current_exception();
    }
    std::uint64_t meshId = 0;
    bool hasMesh = false;
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mMutex);
            mWake.wait(lock, [&] { return mStop || mPending.has_value(); });
            if (mStop) break;
            job = std::move(*mPending);
            mPending.reset();
            mRunning = true;
        }
        GdmPicture picture;
        picture.job = job.number;
        picture.frame = job.frame;
        const auto start = std::chrono::steady_clock::now();
        if (startFailure) {
            picture.error = startFailure;
        } else {
            try {
                if (!hasMesh || meshId != job.frame.mesh) {
                    view->setMesh(job.mesh, job.frame.mesh);
                    meshId = job.frame.mesh;
                    hasMesh = true;
                }
                picture.image = view->render(job.frame);
            } catch (...) {
                picture.error = std::current_exception();
            }
        }
        picture.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        {
            std::lock_guard lock(mMutex);
            mResult = std::move(picture);
            mFinished = job.number;
            mRunning = false;
        }
        mDone.notify_all();
    }
    view.reset();  // its GL objects while the context is current
    if (current) release();
}

}  // namespace strata::view
