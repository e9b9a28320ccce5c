// Internal to strata-view: the viewer's state and its frame loop (viewer.cpp) and panels
// (viewer_panels.cpp). The public entry point is runViewer (viewer.h).
#pragma once

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
#include <filesystem>
#include <memory>
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

// The window and its OpenGL 4.5 core context, current on the calling thread.
class Window {
public:
    Window(int width, int height, const std::string& title, bool vsync);
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

class Viewer {
public:
    Viewer(const ViewerOptions& options, Scene scene, Material material, Mesh mesh);
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
    Image readWindow(int width, int height) const;
    void saveScreenshot(const std::filesystem::path& path, const Image& image) const;
    std::vector<std::filesystem::path> inputs() const;

    // viewer_panels.cpp
    void drawPanels();
    void scenePanel();
    void materialPanel();
    void layerControls(int index, int& removeIndex, int& moveFrom, int& moveTo);
    void addLayerControls();
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

    // Destroyed in reverse order: GL objects while the context still exists, then ImGui, window, GLFW.
    GlfwLibrary mGlfw;
    Window mWindow;
    ImGuiLayer mImGui;
    std::unique_ptr<gl::ReliefRenderer> mRenderer;
    gl::GpuMesh mGpuMesh;
    MaterialPipeline mPipeline;
    const gl::GpuMaterial* mGpuMaterial = nullptr;
};

}  // namespace strata::view
