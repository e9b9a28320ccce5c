// Internal to strata-view: the viewer's state and its frame loop (viewer.cpp) and panels
// (viewer_panels.cpp). The public entry point is runViewer (viewer.h).
#pragma once

#include "gdm_view.h"
#include "material_document.h"
#include "material_pipeline.h"
#include "orbit_camera.h"
#include "viewer.h"

#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/image/image.h"
#include "strata/mesh/mesh.h"
#include "strata/scene/scene.h"

#include <array>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace strata::view {

// Owns glfwInit / glfwTerminate. Throws Error(Unsupported) when GLFW cannot reach a display.
class GlfwLibrary {
public:
    GlfwLibrary();
    ~GlfwLibrary();
    GlfwLibrary(const GlfwLibrary&) = delete;
    GlfwLibrary& operator=(const GlfwLibrary&) = delete;
};

// The window and its OpenGL 4.5 core context, current on the calling thread. A hidden one (visible false)
// only lends its context to another thread (the GDM worker's): it leaves the calling thread's context
// current as it was.
class Window {
public:
    Window(int width, int height, const std::string& title, bool vsync, bool visible = true);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
    GLFWwindow* handle() const { return mWindow; }

private:
    GLFWwindow* mWindow = nullptr;
};

// Dear ImGui's context with its GLFW and OpenGL 3 backends.
class ImGuiLayer {
public:
    explicit ImGuiLayer(GLFWwindow* window);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;
};

// The mean of the last kCount values.
class RollingMean {
public:
    void add(double value);
    double mean() const;
    bool empty() const { return mCount == 0; }

private:
    static constexpr int kCount = 60;
    std::array<double, kCount> mValues{};
    int mCount = 0;
    int mNext = 0;
};

// A picture in a texture, shown over the whole window (the GDM mode's: GdmRenderer reads its pictures back,
// so they come to the window as images). Needs the window's context current, also when destroyed.
class PictureTexture {
public:
    PictureTexture() = default;
    ~PictureTexture();
    PictureTexture(const PictureTexture&) = delete;
    PictureTexture& operator=(const PictureTexture&) = delete;

    // A 3-channel sRGB picture, row 0 at the top, quantised to 8 bits (toUnorm8, no dither).
    void upload(const Image& srgb);
    // Copies it to the window's back buffer, scaled to width x height (1:1 and exact at its own size,
    // linear otherwise); false when there is none yet.
    bool blit(int width, int height) const;
    int width() const { return mWidth; }
    int height() const { return mHeight; }

private:
    unsigned mTexture = 0;
    unsigned mFramebuffer = 0;
    int mWidth = 0;
    int mHeight = 0;
};

class Viewer {
public:
    // `gdm`: the GDM mode (the material is not used); null: the relief mode.
    Viewer(const ViewerOptions& options, Scene scene, Material material, Mesh mesh,
           std::shared_ptr<const SceneGdm> gdm = nullptr);
    ~Viewer();
    // Runs until the window closes, or until the screenshot is written.
    void run();

private:
    // viewer.cpp
    BakeRequest bakeRequest() const;
    void setMesh(Mesh mesh);
    void resetCamera();
    void handleInput();
    void drawScene(int width, int height);
    void updateLight();
    // GDM mode.
    GdmFrame gdmFrame(int width, int height) const;
    void drawGdm(int width, int height);
    void updateGdmShell();
    Image readWindow(int width, int height) const;
    void saveScreenshot(const std::filesystem::path& path, const Image& image) const;
    std::vector<std::filesystem::path> inputs() const;

    // viewer_panels.cpp
    void drawPanels();
    void scenePanel();
    void reliefControls();
    void materialPanel();
    void materialSaveControls();
    void gdmControls();
    void environmentControls();
    void gdmPanel();
    void layerControls(int index, int& removeIndex, int& moveFrom, int& moveTo);
    void addLayerControls();
    void normalYControl(MaterialLayer& layer);
    void savePanel();
    void statsOverlay();
    void setStatus(std::string message, bool error);

    ViewerOptions mOptions;
    Scene mScene;  // mesh name, relief settings, lighting, background: what `strata render` would use
    Material mMaterial;
    Mesh mMesh;
    Bounds mBounds;
    double mDepthScale = kDefaultDepthScale;  // the render's S
    OrbitCamera mOrbit;
    // The light as the panel shows it: direction from the mesh's centre (degrees) and distance.
    double mLightAzimuth = 0.0;
    double mLightElevation = 0.0;
    double mLightDistance = 0.0;  // 0 until the constructor has read the scene's light
    bool mShowUi = true;
    int mDragButton = -1;  // the mouse button dragging the camera, -1 for none

    // Panel state.
    std::string mMeshFile;
    std::string mAddPattern = "fabric";
    int mAddSeed = 1;
    std::string mAddDepthFile, mAddNormalFile, mAddColorFile;
    bool mAddIsHeight = false;
    int mAddNormalY = 0;  // the added layer's "normal_y": 0 auto (as `strata import`), 1 up, 2 down
    std::string mMaterialPath;
    std::string mScreenshotPath = "strata-view.png";
    bool mScreenshotWithUi = false;
    bool mCaptureRequested = false;
    std::string mStatus;
    bool mStatusIsError = false;

    // Timing.
    RollingMean mFrameMs;
    RollingMean mSceneMs;  // ReliefRenderer::draw up to glFinish
    std::string mRendererName;

    // GDM mode (mGdm set).
    std::shared_ptr<const SceneGdm> mGdm;
    GdmDescription mGdmDescription;
    GdmViewSettings mGdmSettings;  // rank 1..stored or kGdmRankRaw
    int mGdmSamples = 1;           // per pixel, as PictureSettings::samples
    int mGdmPreview = 4;           // while the view changes: pictures at 1 / this of the window's width
    std::shared_ptr<const Mesh> mGdmMesh;  // mMesh, shared with the worker
    std::uint64_t mGdmMeshId = 0;
    PrismShell mGdmShell;  // the current settings' shell on mMesh (its T, tile length)
    std::optional<GdmViewSettings> mGdmShellSettings;     // what mGdmShell was built for
    std::optional<GdmFrame> mGdmWanted;                   // the full picture the view asks for
    std::chrono::steady_clock::time_point mGdmChangedAt;  // when it last changed
    std::optional<GdmFrame> mGdmSubmitted;                // the last frame given to the worker
    std::optional<GdmFrame> mGdmShown;                    // the frame of the picture in the window
    double mGdmPictureMs = 0.0;                           // the last picture's time on the worker

    // Destroyed in reverse order: GL objects while the context still exists, then ImGui, window, GLFW.
    GlfwLibrary mGlfw;
    Window mWindow;
    ImGuiLayer mImGui;
    std::unique_ptr<gl::ReliefRenderer> mRenderer;
    gl::GpuMesh mGpuMesh;
    MaterialPipeline mPipeline;
    const gl::GpuMaterial* mGpuMaterial = nullptr;
    // GDM mode: the window's picture, then the worker's hidden window (its context) and the worker, which
    // stops (and releases that context) before the window goes.
    PictureTexture mPicture;
    std::unique_ptr<Window> mGdmContext;
    std::unique_ptr<GdmWorker> mGdmWorker;
};

}  // namespace strata::view
