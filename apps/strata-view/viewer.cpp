#include "viewer_app.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/gl/gl_error.h"
#include "strata/image/image_io.h"

// libepoxy resolves GL in whatever context is current (GLX here, EGL in the headless tools); GLFW must not
// include a GL header of its own.
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cmath>
#include <iostream>

namespace fs = std::filesystem;

namespace strata::view {

namespace {

// GLFW reports errors through a callback without a user pointer; the last message explains a failed call.
std::string gGlfwError;

void glfwErrorCallback(int code, const char* message) {
    gGlfwError =
        std::string(message ? message : "unknown error") + " (GLFW error " + std::to_string(code) + ")";
}

constexpr double kOrbitDegreesPerPixel = 0.35;
constexpr double kZoomPerWheelStep = 0.85;

}  // namespace

// --- GLFW, window, ImGui --------------------------------------------------------------------------------

GlfwLibrary::GlfwLibrary() {
    glfwSetErrorCallback(glfwErrorCallback);
    if (!glfwInit()) {
        throw Error(ErrorKind::Unsupported,
                    "cannot open a window: " + gGlfwError +
                        ". strata-view needs a display; without one, run it under a virtual one: "
                        "xvfb-run -a strata-view ...");
    }
}

GlfwLibrary::~GlfwLibrary() {
    glfwTerminate();
}

Window::Window(int width, int height, const std::string& title, bool vsync) {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#ifndef NDEBUG
    // As HeadlessContext does in debug builds: checkGl() then reports the driver's own message.
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    // The renderer writes sRGB-encoded values itself (ReliefRenderer::draw): no sRGB framebuffer.
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    mWindow = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!mWindow) {
        throw Error(
            ErrorKind::Unsupported,
            "no OpenGL 4.5 core context for a " + std::to_string(width) + "x" + std::to_string(height) +
                " window: " + gGlfwError +
                ". strata-view needs OpenGL 4.5 (Mesa's llvmpipe has it: xvfb-run -a strata-view ...)");
    }
    glfwMakeContextCurrent(mWindow);
    if (epoxy_gl_version() < 45) {
        const std::string version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
        glfwDestroyWindow(mWindow);
        throw Error(ErrorKind::Unsupported, "the window's OpenGL context is " + version + ", not 4.5 core");
    }
    glfwSwapInterval(vsync ? 1 : 0);
#ifndef NDEBUG
    gl::installDebugOutput();
#endif
}

Window::~Window() {
    glfwDestroyWindow(mWindow);
}

ImGuiLayer::ImGuiLayer(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the working directory: tests and scripts run from anywhere
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 4.0f;
    // ImGui's OpenGL 3 backend loads the GL functions it needs itself (its bundled gl3w, through
    // libGL.so.1 and glXGetProcAddress), separately from libepoxy; both see the same current context.
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true) || !ImGui_ImplOpenGL3_Init("#version 450 core")) {
        ImGui::DestroyContext();
        throw Error(ErrorKind::Runtime, "Dear ImGui's GLFW / OpenGL 3 backend failed to initialise");
    }
}

ImGuiLayer::~ImGuiLayer() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

// --- timing ---------------------------------------------------------------------------------------------

void RollingMean::add(double value) {
    mValues[mNext] = value;
    mNext = (mNext + 1) % kCount;
    mCount = std::min(mCount + 1, kCount);
}

double RollingMean::mean() const {
    double sum = 0.0;
    for (int i = 0; i < mCount; ++i) sum += mValues[i];
    return mCount > 0 ? sum / mCount : 0.0;
}

// --- the viewer -----------------------------------------------------------------------------------------

Viewer::Viewer(const ViewerOptions& options, Scene scene, Material material, Mesh mesh)
    : mOptions(options),
      mScene(std::move(scene)),
      mMaterial(std::move(material)),
      mShowUi(!options.hideUi),
      mMaterialPath(mMaterial.source.extension() == ".json" && mMaterial.source.filename() != "strata.json"
                        ? mMaterial.source.string()
                        : std::string("material.json")),
      mWindow(options.width, options.height, "strata-view", options.screenshot.empty()),
      mImGui(mWindow.handle()) {
    mRenderer = std::make_unique<gl::ReliefRenderer>();
    mRendererName = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    mDepthScale = mScene.relief.depthScale.value_or(mMaterial.compose.depthScale);
    setMesh(std::move(mesh));
    if (mScene.camera) mOrbit = OrbitCamera(*mScene.camera);
    // The light panel edits a direction from the mesh's centre; the scene's position is kept exactly until
    // it is touched (so that the first frames match `strata render` of the same scene).
    const glm::dvec3 centre = 0.5 * (glm::dvec3(mBounds.min) + glm::dvec3(mBounds.max));
    const glm::dvec3 offset = mScene.lighting.lightPosition - centre;
    mLightDistance = std::max(glm::length(offset), 1e-6);
    mLightAzimuth = glm::degrees(std::atan2(offset.y, offset.x));
    mLightElevation = glm::degrees(std::asin(std::clamp(offset.z / mLightDistance, -1.0, 1.0)));
}

Viewer::~Viewer() = default;

BakeRequest Viewer::bakeRequest() const {
    BakeRequest request;
    request.material = mMaterial;
    request.resolution = mOptions.resolution;
    request.renderDepthScale = mDepthScale;
    request.aoRescale = mScene.relief.aoRescale;
    request.meta = mScene.meta;
    return request;
}

void Viewer::setMesh(Mesh mesh) {
    gl::GpuMesh gpuMesh = gl::uploadMesh(mesh);  // throws for a bad mesh before anything changes
    mGpuMesh = std::move(gpuMesh);
    mBounds = meshBounds(mesh);
    mMesh = std::move(mesh);
    resetCamera();
    updateLight();
}

void Viewer::resetCamera() {
    int width = 0, height = 0;
    glfwGetFramebufferSize(mWindow.handle(), &width, &height);
    const double aspect = width > 0 && height > 0 ? static_cast<double>(width) / height : 16.0 / 9.0;
    // What `strata render` does for a scene without a camera.
    mOrbit = OrbitCamera(frameCamera(mBounds, aspect));
}

void Viewer::updateLight() {
    if (mLightDistance <= 0.0) return;  // not set up yet (the constructor sets it after the first mesh)
    const glm::dvec3 centre = 0.5 * (glm::dvec3(mBounds.min) + glm::dvec3(mBounds.max));
    const double azimuth = glm::radians(mLightAzimuth);
    const double elevation = glm::radians(mLightElevation);
    const glm::dvec3 direction(std::cos(elevation) * std::cos(azimuth),
                               std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    mScene.lighting.lightPosition = centre + mLightDistance * direction;
}

std::vector<fs::path> Viewer::inputs() const {
    std::vector<fs::path> files = materialInputs(mMaterial);
    if (fs::exists(mMesh.name)) files.push_back(mMesh.name);
    if (!mOptions.sceneFile.empty()) files.push_back(mOptions.sceneFile);
    return files;
}

void Viewer::handleInput() {
    const ImGuiIO& io = ImGui::GetIO();
    // A drag belongs to the camera if it started outside every panel.
    for (int button = 0; button < 3; ++button)
        if (mDragButton < 0 && ImGui::IsMouseClicked(button) && !io.WantCaptureMouse) mDragButton = button;
    if (mDragButton >= 0 && !ImGui::IsMouseDown(mDragButton)) mDragButton = -1;

    const double dx = io.MouseDelta.x;
    const double dy = io.MouseDelta.y;
    const double height = std::max(1.0f, io.DisplaySize.y);
    if (mDragButton == 0 && !io.KeyShift) {
        mOrbit.orbit(-dx * kOrbitDegreesPerPixel, dy * kOrbitDegreesPerPixel);
    } else if (mDragButton >= 0) {
        // Right or middle drag, or shift + left: the scene follows the cursor.
        mOrbit.pan(-dx / height, dy / height);
    }
    if (!io.WantCaptureMouse && io.MouseWheel != 0.0f)
        mOrbit.zoom(std::pow(kZoomPerWheelStep, io.MouseWheel));

    if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed(GLFW_KEY_H, false)) mShowUi = !mShowUi;
        if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) resetCamera();
        if (ImGui::IsKeyPressed(GLFW_KEY_S, false)) mCaptureRequested = true;
    }
}

void Viewer::drawScene(int width, int height) {
    gl::RenderRequest request;
    request.objects.push_back({&mGpuMesh, glm::dmat4(1.0), mGpuMaterial, glm::dvec3(0.8)});
    request.camera = mOrbit.camera();
    request.relief = mScene.relief;
    request.relief.depthScale = mDepthScale;
    request.lighting = mScene.lighting;
    request.picture = mScene.picture;
    // The scene's time is measured to glFinish: a GL timer query would be the better measure on a GPU, but
    // llvmpipe rasterises when the commands are flushed, after such a query has ended, so the query reads a
    // fraction of the frame. The wait costs a GPU some CPU/GPU overlap, which an interactive viewer can
    // spare.
    const auto start = std::chrono::steady_clock::now();
    try {
        mRenderer->draw(request, width, height);
    } catch (const Error& e) {
        // A setting the material cannot be drawn with (maxmip with a live material): the window shows the
        // background and the panel the reason. --screenshot has nothing to show: its exit code says why.
        if (!mOptions.screenshot.empty()) throw;
        setStatus(e.what(), true);
        const glm::dvec3 background = mScene.picture.background;
        glClearColor(static_cast<float>(background.r), static_cast<float>(background.g),
                     static_cast<float>(background.b), 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glFinish();
    mSceneMs.add(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

Image Viewer::readWindow(int width, int height) const {
    std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    gl::checkGl("strata-view: reading the window back");
    Image image = Image::uninitialized(width, height, 3);
    for (int y = 0; y < height; ++y) {
        // GL's row 0 is the bottom one; a picture's row 0 is the top (CONVENTIONS §7).
        const unsigned char* source = pixels.data() + static_cast<std::size_t>(height - 1 - y) * width * 4;
        float* row = image.row(y);
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) row[x * 3 + c] = static_cast<float>(source[x * 4 + c]) / 255.0f;
    }
    return image;
}

void Viewer::saveScreenshot(const fs::path& path, const Image& image) const {
    refuseToOverwriteInputs(path, inputs());
    try {
        if (path.has_parent_path()) fs::create_directories(path.parent_path());
    } catch (const fs::filesystem_error& e) {
        throw Error(ErrorKind::Io, path.string() + ": cannot create its directory: " + e.code().message());
    }
    PngWriteOptions png;
    png.bitDepth = PngBitDepth::Eight;
    png.dither = false;          // the window holds 8-bit values already; a dither would change them
    writePng(path, image, png);  // atomic: a temporary file renamed into place
}

void Viewer::run() {
    const bool screenshotMode = !mOptions.screenshot.empty();
    // The first material before the first frame: there is nothing to show without it, and its failure is
    // the input's (a bad layer file), reported with its exit code.
    mGpuMaterial = mPipeline.updateAndWait(bakeRequest());

    auto lastSwap = std::chrono::steady_clock::now();
    RollingMean screenshotFrames;  // frames after the first (which builds the shader programs)
    for (int frame = 0; !glfwWindowShouldClose(mWindow.handle()); ++frame) {
        glfwPollEvents();
        int width = 0, height = 0;
        glfwGetFramebufferSize(mWindow.handle(), &width, &height);
        if (width <= 0 || height <= 0) {  // minimised
            glfwWaitEvents();
            continue;
        }

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        if (!screenshotMode) handleInput();
        if (mShowUi) drawPanels();
        ImGui::Render();

        mGpuMaterial = mPipeline.update(bakeRequest());
        drawScene(width, height);
        const bool lastFrame = screenshotMode && frame + 1 >= mOptions.frames;
        std::optional<Image> capture;
        if (mCaptureRequested && !mScreenshotWithUi) capture = readWindow(width, height);
        if (mShowUi) ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if ((mCaptureRequested && mScreenshotWithUi) || lastFrame) capture = readWindow(width, height);
        gl::checkGl("strata-view: frame");
        glfwSwapBuffers(mWindow.handle());

        const auto now = std::chrono::steady_clock::now();
        const double frameMs = std::chrono::duration<double, std::milli>(now - lastSwap).count();
        lastSwap = now;
        mFrameMs.add(frameMs);
        if (frame > 0) screenshotFrames.add(frameMs);

        if (lastFrame) {
            saveScreenshot(mOptions.screenshot, *capture);
            std::cout << "wrote " << mOptions.screenshot.string() << " (" << width << "x" << height << ", "
                      << mOptions.frames << " frames";
            if (!screenshotFrames.empty())
                std::cout << ", " << std::round(screenshotFrames.mean() * 10.0) / 10.0
                          << " ms per frame after the first";
            std::cout << ", " << mRendererName << ")\n";
            return;
        }
        if (mCaptureRequested) {
            mCaptureRequested = false;
            try {
                saveScreenshot(mScreenshotPath, *capture);
                setStatus("wrote " + mScreenshotPath, false);
            } catch (const Error& e) {
                setStatus(e.what(), true);
            }
        }
    }
}

// --- entry point ----------------------------------------------------------------------------------------

void runViewer(const ViewerOptions& options) {
    // Everything that can be wrong with the input is found before a window opens.
    Scene scene = options.sceneFile.empty() ? Scene{} : readScene(options.sceneFile);
    if (!scene.depthMap.empty())
        throw Error(ErrorKind::Unsupported, options.sceneFile.string() +
                                                ": depth_map: the viewer shows materials, not a bare depth "
                                                "map (use `strata render` for the verification scene)");
    if (!options.mesh.empty()) scene.mesh = options.mesh;
    if (!options.meta.empty()) scene.meta = parseMetaPath(options.meta);
    Material material = openMaterial(options.material.empty() ? scene.material : options.material);
    Mesh mesh = loadSceneMesh(scene);
    if (!options.screenshot.empty()) {
        if (lowerCaseExtension(options.screenshot) != ".png")
            throw Error(ErrorKind::Unsupported,
                        options.screenshot.string() + ": --screenshot writes PNG only (a .png file name)");
        std::vector<fs::path> inputs = materialInputs(material);
        if (fs::exists(scene.mesh)) inputs.push_back(scene.mesh);
        if (!options.sceneFile.empty()) inputs.push_back(options.sceneFile);
        refuseToOverwriteInputs(options.screenshot, inputs);
    }
    Viewer viewer(options, std::move(scene), std::move(material), std::move(mesh));
    viewer.run();
}

}  // namespace strata::view
