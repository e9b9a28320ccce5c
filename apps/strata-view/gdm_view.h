// strata-view's GDM mode (docs/viewer.md, "GDM materials"): a generalized displacement map (Wang et al.
// 2004) drawn in the prism shell of the viewer's mesh by strata::gl's GdmRenderer, as `strata render --gdm`
// draws it (apps/strata/render_gdm.cpp): the same renderer, the same picture (gl::renderGdmPicture).
//
// GdmRenderer reads its pictures back into an Image, so the viewer draws a GDM frame offscreen and shows the
// picture in the window (viewer.cpp). A GDM frame costs seconds on llvmpipe at 1280x720, so the pictures
// are drawn on a worker thread with its own GL context (GdmWorker) while the window keeps drawing the last
// one; a picture is drawn only when what it depends on (GdmFrame) changed.
//
//   GdmView    the renderer with the GDM, the mesh's shell and the volumes uploaded (and, with an
//              environment, the RTV, the mesh's macro transfer and the turned environment); render(frame)
//              applies what changed (a rank uploads the truncated SVD, a tiling or a thickness rebuilds the
//              shell, a rotation or an intensity only turns the environment) and draws. No window, no
//              thread: tests drive it on a headless context.
//   GdmWorker  a GdmView on a thread of its own, fed the latest frame; the window's thread takes the
//              pictures.
#pragma once

#include "strata/gdm/macro_transfer.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/scene_gdm.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/image/image.h"
#include "strata/mesh/mesh.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>

namespace strata::view {

// What the GDM panel edits (the scene's GdmSettings and its tiling).
struct GdmViewSettings {
    GdmTechnique technique = GdmTechnique::Gdm;
    // The GDM the lookups read: 1..the stored rank (truncateGdmSvd of the stored SVD; never a re-bake), or
    // kGdmRankRaw (the asset's raw GDM, when it has one). 0 is read as the stored rank.
    int rank = 0;
    // T, the shell's thickness in world units (> 0); nullopt: H times the world length of one tile.
    std::optional<double> shellThickness;
    double tiling = 1.0;  // tiles per unit of mesh uv, > 0
    GdmLightFrame lightFrame =
        GdmLightFrame::Tangent;  // the shadow lookup's light direction in texture space
    // The environment's turn about world +z (degrees, towards +y) and its radiance's scale, as the scene's
    // env_rotation and env_intensity (EnvironmentSettings): live, no re-bake. Unused without an environment.
    double environmentRotation = 0.0;
    double environmentIntensity = 1.0;

    bool operator==(const GdmViewSettings&) const = default;
};

// Everything one GDM picture depends on.
struct GdmFrame {
    GdmViewSettings settings;
    Camera camera;
    Lighting lighting;  // the point light (position, world units) and the Blinn-Phong terms
    int width = 1;      // pixels
    int height = 1;
    int samples = 1;                          // PictureSettings::samples: a k x k grid, k = round(sqrt(n))
    glm::dvec3 background{0.16, 0.17, 0.19};  // sRGB, PictureSettings::background
    std::uint64_t mesh = 0;                   // which mesh (the caller's count of mesh changes)
};
bool sameFrame(const GdmFrame& a, const GdmFrame& b);

// The picture settings of a frame: the shaded output, as `strata render` would draw it.
PictureSettings gdmPictureSettings(const GdmFrame& frame);

// The prism shell `settings` give on `mesh` for `gdm` (buildPrismShell with H the GDM's, tiling and
// thickness the settings'): its thickness T and tile length, for the panel and for framing. Throws as
// buildPrismShell (a thickness that is not > 0, a mesh without uvs).
PrismShell gdmShell(const SceneGdm& gdm, const Mesh& mesh, const GdmViewSettings& settings);

// The bounds `strata render --gdm` frames a scene without a camera on: the mesh's, grown by T on every side
// (they hold everything the GDM can draw).
Bounds gdmFramingBounds(const Mesh& mesh, double thickness);

// The GDM panel's description of a loaded GDM.
struct GdmDescription {
    std::string source;      // SceneGdm::description up to its rank: "meso weave (baked on the fly)", a path
    std::string dims;        // "64 x 64 x 16 voxels, 16 x 32 directions"
    double height = 0.0;     // H, tile widths
    int storedRank = 0;      // the asset's SVD rank
    bool hasRaw = false;     // whether rank "raw" is offered
    double svdMiB = 0.0;     // the stored SVD's maps (W and E, float)
    double rawMiB = 0.0;     // the raw GDM (0 without one)
    double volumeMiB = 0.0;  // occupancy and albedo volumes
    // The environment (SceneGdm::environmentName, "" without one) and its RTV's SVD terms and maps (W and E).
    std::string environment;
    int rtvRank = 0;
    double rtvMiB = 0.0;
};
GdmDescription describeGdm(const SceneGdm& gdm);

// Whether `gdm` is lit by an environment (loadSceneGdm baked its RTV and opened the environment).
bool hasEnvironment(const SceneGdm& gdm);

// Needs a current OpenGL 4.5 core context on every call, and when destroyed (it owns a gl::GdmRenderer).
class GdmView {
public:
    // Builds the renderer (throws Error(Runtime) if its program does not build). `gdm` is shared with the
    // window's thread, which reads its description; it is never changed.
    explicit GdmView(std::shared_ptr<const SceneGdm> gdm);
    ~GdmView();
    GdmView(const GdmView&) = delete;
    GdmView& operator=(const GdmView&) = delete;

    // The mesh whose shell is drawn, with the caller's number for it (GdmFrame::mesh). The shell is built
    // at the next render().
    void setMesh(std::shared_ptr<const Mesh> mesh, std::uint64_t id);

    // The picture of `frame` (gl::renderGdmPicture: sRGB, 3 channels, width x height), as `strata render
    // --gdm` draws it (gl::prepareGdmRenderer). Uploads what changed since the last call: the GDM for a new
    // rank (the truncated SVD, or the raw GDM), with the shell and the volumes after it (GdmRenderer::setGdm
    // forgets them); the shell alone for a new mesh, tiling or thickness. With an environment
    // (hasEnvironment): a new rank uploads the RTV again (setGdm forgets it); a new shell sets the macro
    // transfer and the environment again (setMesh forgets them), the macro transfer baked again only for a
    // new mesh or a new thickness T (bakeMacroTransfer from the top of the shell; a tiling that leaves T as
    // it was reuses the last bake); a new rotation or intensity sets the environment alone
    // (turnEnvironment of SceneGdm::environmentSh: per-vertex products on the CPU and one buffer upload).
    // A technique, camera, light or size changes nothing but the picture. Throws
    // Error(InvalidInput) for a rank the asset lacks (above the stored one, raw without a raw GDM) or a
    // frame's mesh that was not set, and as buildPrismShell and renderGdmPicture; after a throw the next
    // call uploads everything again.
    Image render(const GdmFrame& frame);

    // Counters, for tests and the panel: GDM uploads (setGdm), shell builds (setMesh), pictures drawn;
    // with an environment, RTV uploads (setRtv), macro transfer bakes (bakeMacroTransfer) and uploads
    // (setMacroTransfer), environment uploads (setEnvironment).
    int gdmUploads() const { return mGdmUploads; }
    int shellBuilds() const { return mShellBuilds; }
    int renders() const { return mRenders; }
    int rtvUploads() const { return mRtvUploads; }
    int macroTransferBakes() const { return mMacroTransferBakes; }
    int macroTransferUploads() const { return mMacroTransferUploads; }
    int environmentUploads() const { return mEnvironmentUploads; }

private:
    std::shared_ptr<const SceneGdm> mGdm;
    gl::GdmRenderer mRenderer;
    std::shared_ptr<const Mesh> mMesh;
    std::uint64_t mMeshId = 0;
    // What the renderer holds: nullopt until uploaded (and after a failure).
    std::optional<int> mUploadedRank;
    std::optional<std::tuple<std::uint64_t, double, std::optional<double>>> mUploadedShell;
    bool mUploadedRtv = false;
    bool mUploadedMacroTransfer = false;
    std::optional<std::pair<double, double>> mUploadedEnvironment;  // rotation, intensity
    // The last macro transfer baked, for the mesh and T it was baked for (kept across shell rebuilds that
    // leave both as they were).
    MacroTransfer mMacroTransfer;
    std::optional<std::pair<std::uint64_t, double>> mMacroTransferKey;
    int mGdmUploads = 0;
    int mShellBuilds = 0;
    int mRenders = 0;
    int mRtvUploads = 0;
    int mMacroTransferBakes = 0;
    int mMacroTransferUploads = 0;
    int mEnvironmentUploads = 0;
};

// A finished picture (or why there is none).
struct GdmPicture {
    std::uint64_t job = 0;  // submit()'s number
    GdmFrame frame;
    Image image;               // empty on a failure
    double seconds = 0.0;      // render(): uploads, the draw and the read-back
    std::exception_ptr error;  // the failure, null on success
};

// A GdmView on a thread of its own. `makeCurrent` and `release` run on that thread: the first makes a GL
// context current there (one no other thread uses; the viewer's is a hidden GLFW window's), the second
// makes it not current (after the view is destroyed, when the worker stops).
class GdmWorker {
public:
    GdmWorker(std::shared_ptr<const SceneGdm> gdm, std::function<void()> makeCurrent,
              std::function<void()> release);
    // Stops after the picture in progress and joins the thread.
    ~GdmWorker();
    GdmWorker(const GdmWorker&) = delete;
    GdmWorker& operator=(const GdmWorker&) = delete;

    // Asks for a picture of `frame` (with `mesh`, frame.mesh's). A frame submitted while another waits
    // replaces it: only the latest is drawn. Returns the job's number.
    std::uint64_t submit(const GdmFrame& frame, std::shared_ptr<const Mesh> mesh);
    // The newest finished picture not taken yet, if any.
    std::optional<GdmPicture> take();
    // Waits for job `job` (or a later one) to finish and returns the newest picture. For a caller that
    // does not take() meanwhile (--screenshot draws and waits, frame by frame).
    GdmPicture wait(std::uint64_t job);
    // Whether a picture is being drawn or waits to be.
    bool busy() const;

private:
    void loop(std::shared_ptr<const SceneGdm> gdm, std::function<void()> makeCurrent,
              std::function<void()> release);

    struct Job {
        std::uint64_t number = 0;
        GdmFrame frame;
        std::shared_ptr<const Mesh> mesh;
    };
    mutable std::mutex mMutex;
    std::condition_variable mWake;  // a job or stop, for the worker
    std::condition_variable mDone;  // a picture, for wait()
    std::optional<Job> mPending;
    bool mRunning = false;  // a job is being drawn
    bool mStop = false;
    std::uint64_t mSubmitted = 0;
    std::uint64_t mFinished = 0;
    std::optional<GdmPicture> mResult;  // the newest, until taken
    std::thread mThread;                // last: started once everything above exists
};

}  // namespace strata::view
