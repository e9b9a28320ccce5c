#include "viewer_app.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/gl/gl_error.h"
#include "strata/image/image_io.h"
#include "strata/image/quantize.h"

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
// GDM mode: how long the view must rest before the full picture replaces the smaller previews. A drag
// sends a new camera every frame; a pause shorter than this still counts as moving.
constexpr auto kGdmRestTime = std::chrono::milliseconds(400);
// GDM mode: the longest the window waits for an event between frames (s), when nothing happens.
constexpr double kGdmIdleFrame = 1.0 / 30.0;

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

Window::Window(int width, int height, const std::string& title, bool vsync, bool visible) {
    GLFWwindow* const previous = glfwGetCurrentContext();
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
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
#ifndef NDEBUG
    gl::installDebugOutput();
#endif
    if (!visible) {
        glfwMakeContextCurrent(previous);  // the thread that uses it makes it current there
        return;
    }
    glfwSwapInterval(vsync ? 1 : 0);
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

// --- the GDM mode's picture -----------------------------------------------------------------------------

PictureTexture::~PictureTexture() {
    if (mFramebuffer != 0) glDeleteFramebuffers(1, &mFramebuffer);
    if (mTexture != 0) glDeleteTextures(1, &mTexture);
}

void PictureTexture::upload(const Image& srgb) {
    STRATA_CHECK_EQ(srgb.channels(), 3);
    const int width = srgb.width(), height = srgb.height();
    if (width != mWidth || height != mHeight) {
        if (mTexture != 0) glDeleteTextures(1, &mTexture);
        glCreateTextures(GL_TEXTURE_2D, 1, &mTexture);
        glTextureStorage2D(mTexture, 1, GL_RGBA8, width, height);
        if (mFramebuffer == 0) glCreateFramebuffers(1, &mFramebuffer);
        glNamedFramebufferTexture(mFramebuffer, GL_COLOR_ATTACHMENT0, mTexture, 0);
        glNamedFramebufferReadBuffer(mFramebuffer, GL_COLOR_ATTACHMENT0);
        mWidth = width;
        mHeight = height;
    }
    // 8 bits as the window holds them, rounded (the screenshot reads them back as they are); GL's row 0 is
    // the bottom one, a picture's the top (CONVENTIONS §7).
    std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height * 4);
    for (int y = 0; y < height; ++y) {
        const float* row = srgb.row(height - 1 - y);
        unsigned char* out = pixels.data() + static_cast<std::size_t>(y) * width * 4;
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c) out[x * 4 + c] = toUnorm8(static_cast<double>(row[x * 3 + c]));
            out[x * 4 + 3] = 255;
        }
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(mTexture, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    gl::checkGl("strata-view: uploading the GDM picture");
}

bool PictureTexture::blit(int width, int height) const {
    if (mTexture == 0) return false;
    glDisable(GL_SCISSOR_TEST);  // a blit is scissored
    const bool exact = width == mWidth && height == mHeight;
    glBlitNamedFramebuffer(mFramebuffer, 0, 0, 0, mWidth, mHeight, 0, 0, width, height, GL_COLOR_BUFFER_BIT,
                           exact ? GL_NEAREST : GL_LINEAR);
    return true;
}

// --- the viewer -----------------------------------------------------------------------------------------

Viewer::Viewer(const ViewerOptions& options, Scene scene, Material material, Mesh mesh,
               std::shared_ptr<const SceneGdm> gdm)
    : mOptions(options),
      mScene(std::move(scene)),
      mMaterial(std::move(material)),
      mShowUi(!options.hideUi),
      mMaterialPath(mMaterial.source.extension() == ".json" && mMaterial.source.filename() != "strata.json"
                        ? mMaterial.source.string()
                        : std::string("material.json")),
      mWindow(options.width, options.height, "strata-view", options.screenshot.empty()),
      mImGui(mWindow.handle()) {
    mRendererName = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    mDepthScale = mScene.relief.depthScale.value_or(mMaterial.compose.depthScale);
    if (gdm) {
        mGdm = std::move(gdm);
        mGdmDescription = describeGdm(*mGdm);
        mGdmSettings.technique = mScene.gdm.technique;
        mGdmSettings.rank = mScene.gdm.rank == 0 ? mGdmDescription.storedRank : mScene.gdm.rank;
        mGdmSettings.shellThickness = mScene.gdm.shellThickness;
        mGdmSettings.tiling = mScene.relief.tiling;
        mGdmSettings.lightFrame = mScene.gdm.lightFrame;
        mGdmSettings.environmentRotation = mScene.environment.rotation;
        mGdmSettings.environmentIntensity = mScene.environment.intensity;
        // The worker draws with a context of its own, a hidden window's, current on its thread only.
        mGdmContext = std::make_unique<Window>(16, 16, "strata-view GDM", false, false);
        GLFWwindow* const context = mGdmContext->handle();
        mGdmWorker = std::make_unique<GdmWorker>(
            mGdm, [context] { glfwMakeContextCurrent(context); }, [] { glfwMakeContextCurrent(nullptr); });
    } else {
        mRenderer = std::make_unique<gl::ReliefRenderer>();
    }
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
    // Both throw for a bad mesh before anything changes.
    if (mGdm) {
        mGdmShell = gdmShell(*mGdm, mesh, mGdmSettings);
        mGdmShellSettings = mGdmSettings;
        mGdmMesh = std::make_shared<const Mesh>(mesh);
        ++mGdmMeshId;
    } else {
        gl::GpuMesh gpuMesh = gl::uploadMesh(mesh);
        mGpuMesh = std::move(gpuMesh);
    }
    mBounds = meshBounds(mesh);
    mMesh = std::move(mesh);
    resetCamera();
    updateLight();
}

void Viewer::resetCamera() {
    int width = 0, height = 0;
    glfwGetFramebufferSize(mWindow.handle(), &width, &height);
    const double aspect = width > 0 && height > 0 ? static_cast<double>(width) / height : 16.0 / 9.0;
    // What `strata render` does for a scene without a camera (with a GDM: on the shell's bounds).
    mOrbit = OrbitCamera(frameCamera(mGdm ? gdmFramingBounds(mMesh, mGdmShell.thickness) : mBounds, aspect));
}

void Viewer::updateGdmShell() {
    // Only the tiling and T change the shell.
    const bool same = mGdmShellSettings && mGdmShellSettings->tiling == mGdmSettings.tiling &&
                      mGdmShellSettings->shellThickness == mGdmSettings.shellThickness;
    mGdmShellSettings = mGdmSettings;
    if (same) return;
    try {
        mGdmShell = gdmShell(*mGdm, mMesh, mGdmSettings);
    } catch (const Error& e) {
        // The panel keeps the previous shell's numbers; the worker reports the same failure for the picture.
        setStatus(e.what(), true);
    }
}

GdmFrame Viewer::gdmFrame(int width, int height) const {
    GdmFrame frame;
    frame.settings = mGdmSettings;
    frame.camera = mOrbit.camera();
    frame.lighting = mScene.lighting;
    frame.width = width;
    frame.height = height;
    frame.samples = mGdmSamples;
    frame.background = mScene.picture.background;
    frame.mesh = mGdmMeshId;
    return frame;
}

void Viewer::drawGdm(int width, int height) {
    const GdmFrame full = gdmFrame(width, height);
    const auto now = std::chrono::steady_clock::now();
    if (!mGdmWanted || !sameFrame(*mGdmWanted, full)) {
        mGdmWanted = full;
        mGdmChangedAt = now;
    }
    std::optional<GdmPicture> picture;
    if (!mOptions.screenshot.empty()) {
        // Every frame draws its picture and waits for it, so that the screenshot's frame-time line measures
        // a GDM frame (the drawing, the read-back and the upload), and the picture is the full one.
        picture = mGdmWorker->wait(mGdmWorker->submit(full, mGdmMesh));
        if (picture->error) std::rethrow_exception(picture->error);
    } else {
        // While the view changes (a drag, a slider), a smaller picture of one sample per pixel; the full
        // one when it rests. Only the latest frame is drawn (GdmWorker::submit), and only once.
        GdmFrame wanted = full;
        if (mGdmPreview > 1 && now - mGdmChangedAt < kGdmRestTime) {
            wanted.width = std::max(1, width / mGdmPreview);
            wanted.height = std::max(1, height / mGdmPreview);
            wanted.samples = 1;
        }
        if (!mGdmSubmitted || !sameFrame(*mGdmSubmitted, wanted)) {
            mGdmWorker->submit(wanted, mGdmMesh);
            mGdmSubmitted = wanted;
        }
        picture = mGdmWorker->take();
        if (picture && picture->error) {
            try {
                std::rethrow_exception(picture->error);
            } catch (const std::exception& e) {
                setStatus(e.what(), true);
            }
            picture.reset();
        }
    }
    if (picture) {
        mPicture.upload(picture->image);
        mGdmShown = picture->frame;
        mGdmPictureMs = picture->seconds * 1e3;
        mSceneMs.add(mGdmPictureMs);
    }
    const glm::dvec3 background = mScene.picture.background;
    glClearColor(static_cast<float>(background.r), static_cast<float>(background.g),
                 static_cast<float>(background.b), 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    mPicture.blit(width, height);
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
    std::vector<fs::path> files = mGdm ? mGdm->inputs : materialInputs(mMaterial);
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
    // the input's (a bad layer file), reported with its exit code. (A GDM is loaded already.)
    if (!mGdm) mGpuMaterial = mPipeline.updateAndWait(bakeRequest());

    auto lastSwap = std::chrono::steady_clock::now();
    RollingMean screenshotFrames;  // frames after the first (which builds the shader programs)
    for (int frame = 0; !glfwWindowShouldClose(mWindow.handle()); ++frame) {
        if (mGdm && !screenshotMode) {
            // The window's frames only show the worker's last picture: wait for an event (or the worker's
            // next picture, looked for every kGdmIdleFrame), rather than spin on the cores it draws with.
            glfwWaitEventsTimeout(kGdmIdleFrame);
        } else {
            glfwPollEvents();
        }
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

        if (mGdm) {
            updateGdmShell();
            drawGdm(width, height);
        } else {
            mGpuMaterial = mPipeline.update(bakeRequest());
            drawScene(width, height);
        }
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

namespace {

// The screenshot's name: PNG only, never over one of `inputs`.
void checkScreenshot(const fs::path& screenshot, const std::vector<fs::path>& inputs) {
    if (screenshot.empty()) return;
    if (lowerCaseExtension(screenshot) != ".png")
        throw Error(ErrorKind::Unsupported,
                    screenshot.string() + ": --screenshot writes PNG only (a .png file name)");
    refuseToOverwriteInputs(screenshot, inputs);
}

// --gdm and its settings on the scene (as `strata render`'s flags); a GDM with a material is a usage error.
void applyGdmOptions(const ViewerOptions& options, Scene& scene) {
    GdmSettings& gdm = scene.gdm;
    if (!options.gdm.empty()) gdm.source = options.gdm;
    if (!options.gdmTechnique.empty()) gdm.technique = parseGdmTechnique(options.gdmTechnique);
    if (!options.gdmRank.empty()) {
        try {
            gdm.rank = parseGdmRank(options.gdmRank);
        } catch (const Error& e) {
            throw Error(ErrorKind::Usage, std::string("--gdm-rank: ") + e.what());
        }
    }
    if (options.shellThickness) gdm.shellThickness = *options.shellThickness;
    if (!options.gdmLightFrame.empty()) gdm.lightFrame = parseGdmLightFrame(options.gdmLightFrame);
    if (options.tiling) scene.relief.tiling = *options.tiling;
    // The environment's flags as `strata render`'s (apps/strata/render_common.cpp): range errors name the
    // flag (readScene has checked the scene's keys).
    applyEnvironmentFlags(options.env, scene.environment, !gdm.source.empty());
    if (gdm.source.empty()) {
        if (!options.gdmTechnique.empty() || !options.gdmRank.empty() || options.shellThickness ||
            !options.gdmLightFrame.empty())
            throw Error(ErrorKind::Usage,
                        "--gdm-technique, --gdm-rank, --gdm-light-frame and --shell-thickness go with a GDM "
                        "(--gdm, or a scene's \"gdm\")");
        return;
    }
    if (!options.material.empty())
        throw Error(ErrorKind::Usage,
                    "--gdm shows a mesostructure instead of a material: give no MATERIAL "
                    "with it");
    if (!options.meta.empty())
        throw Error(ErrorKind::Usage, "--meta is a meta-relief material's: a GDM has none");
}

}  // namespace

void runViewer(const ViewerOptions& options) {
    // Everything that can be wrong with the input is found before a window opens.
    Scene scene = options.sceneFile.empty() ? Scene{} : readScene(options.sceneFile);
    if (!scene.depthMap.empty())
        throw Error(ErrorKind::Unsupported, options.sceneFile.string() +
                                                ": depth_map: the viewer shows materials, not a bare depth "
                                                "map (use `strata render` for the verification scene)");
    if (!options.mesh.empty()) scene.mesh = options.mesh;
    applyGdmOptions(options, scene);
    if (!scene.gdm.source.empty()) {
        // The cheap checks first: a built-in GDM takes seconds to bake.
        if (!options.screenshot.empty() && lowerCaseExtension(options.screenshot) != ".png")
            checkScreenshot(options.screenshot, {});
        Mesh mesh = loadSceneMesh(scene);
        auto gdm = std::make_shared<const SceneGdm>(loadSceneGdm(
            scene, [](const std::string& message) { std::cerr << "strata-view: " << message << "\n"; }));
        // The shell of the scene's settings: a thickness or a mesh it refuses is the input's error.
        GdmViewSettings settings;
        settings.tiling = scene.relief.tiling;
        settings.shellThickness = scene.gdm.shellThickness;
        gdmShell(*gdm, mesh, settings);
        std::vector<fs::path> inputs = gdm->inputs;
        if (fs::exists(scene.mesh)) inputs.push_back(scene.mesh);
        if (!options.sceneFile.empty()) inputs.push_back(options.sceneFile);
        checkScreenshot(options.screenshot, inputs);
        Viewer viewer(options, std::move(scene), Material{}, std::move(mesh), std::move(gdm));
        viewer.run();
        return;
    }
    if (!options.meta.empty()) scene.meta = parseMetaPath(options.meta);
    Material material = openMaterial(options.material.empty() ? scene.material : options.material);
    Mesh mesh = loadSceneMesh(scene);
    if (!options.screenshot.empty()) {
        std::vector<fs::path> inputs = materialInputs(material);
        if (fs::exists(scene.mesh)) inputs.push_back(scene.mesh);
        if (!options.sceneFile.empty()) inputs.push_back(options.sceneFile);
        checkScreenshot(options.screenshot, inputs);
    }
    Viewer viewer(options, std::move(scene), std::move(material), std::move(mesh));
    viewer.run();
}

}  // namespace strata::view
