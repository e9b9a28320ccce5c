// The viewer's Dear ImGui panels: Scene (mesh, technique, depth scale, AO, light, camera), Material (the
// meta-relief layers), Save, and the frame-time overlay; in GDM mode the Scene panel's GDM section
// (technique, rank, shell thickness, tiling, the environment's rotation and intensity, samples) and the GDM
// panel (what is loaded) instead of the relief and material ones. Panels only edit the viewer's state; the
// frame loop (viewer.cpp) turns that state into a render request and a bake request (or a GDM frame) every
// frame.
#include "viewer_app.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/relief/patterns.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cstdint>

namespace fs = std::filesystem;

namespace strata::view {

namespace {

constexpr float kPanelWidth = 330.0f;
constexpr float kMargin = 8.0f;
const ImVec4 kErrorColor(1.0f, 0.45f, 0.4f, 1.0f);
const ImVec4 kDimColor(0.65f, 0.65f, 0.65f, 1.0f);

bool sliderDouble(const char* label, double& value, double lo, double hi, const char* format,
                  bool logarithmic = false) {
    return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format,
                               logarithmic ? ImGuiSliderFlags_Logarithmic : ImGuiSliderFlags_None);
}

// A combo over `names`; returns true when the choice changed.
bool comboNames(const char* label, const std::vector<std::string>& names, std::string& current) {
    bool changed = false;
    if (ImGui::BeginCombo(label, current.c_str())) {
        for (const std::string& name : names) {
            const bool selected = name == current;
            if (ImGui::Selectable(name.c_str(), selected) && !selected) {
                current = name;
                changed = true;
            }
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    return changed;
}

// A panel that fits its content, but no taller than the window above the frame-time overlay (it scrolls).
void fitToWindow() {
    const float height = ImGui::GetMainViewport()->WorkSize.y - 2.0f * kMargin - 40.0f;
    ImGui::SetNextWindowSizeConstraints(ImVec2(0.0f, 0.0f), ImVec2(10000.0f, std::max(height, 100.0f)));
}

// A titled separator (ImGui 1.86 has no SeparatorText).
void section(const char* title) {
    ImGui::Spacing();
    ImGui::TextColored(kDimColor, "%s", title);
    ImGui::Separator();
}

std::vector<std::string> patternNames() {
    std::vector<std::string> names;
    for (const PatternInfo& info : patternList()) names.push_back(info.name);
    return names;
}

std::string layerTitle(const MaterialLayer& layer, int index) {
    std::string title = std::to_string(index) + ": ";
    if (layer.pattern) {
        title += *layer.pattern;
        if (!layer.name.empty()) title += " (" + layer.name + ")";
    } else {
        title += layer.name.empty() ? std::string("files") : layer.name;
        title += " (files)";
    }
    return title;
}

}  // namespace

void Viewer::setStatus(std::string message, bool error) {
    mStatus = std::move(message);
    mStatusIsError = error;
}

void Viewer::drawPanels() {
    scenePanel();
    if (mGdm)
        gdmPanel();
    else
        materialPanel();
    statsOverlay();
}

void Viewer::scenePanel() {
    ImGui::SetNextWindowPos(ImVec2(kMargin, kMargin), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(kPanelWidth, 0.0f), ImGuiCond_FirstUseEver);
    fitToWindow();
    if (!ImGui::Begin("Scene")) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(-130.0f);

    // Mesh: a built-in, or a file.
    std::string meshName = fs::exists(mMesh.name) ? std::string("(file)") : mMesh.name;
    if (comboNames("mesh", builtinMeshList(), meshName)) {
        try {
            BuiltinMeshParams params;
            if (mScene.tessellation > 0) params.tessellation = mScene.tessellation;
            setMesh(makeBuiltinMesh(meshName, params));
            mScene.mesh = meshName;
        } catch (const Error& e) {
            setStatus(e.what(), true);
        }
    }
    ImGui::InputTextWithHint("##meshfile", ".obj / .gltf / .glb", &mMeshFile);
    ImGui::SameLine();
    if (ImGui::Button("load mesh")) {
        try {
            setMesh(loadMesh(mMeshFile));
            mScene.mesh = mMeshFile;
            setStatus("loaded " + mMeshFile, false);
        } catch (const Error& e) {
            setStatus(e.what(), true);
        }
    }

    if (mGdm) {
        gdmControls();
    } else {
        reliefControls();
    }

    section("light");
    bool lightChanged = sliderDouble("azimuth", mLightAzimuth, -180.0, 180.0, "%.0f deg");
    lightChanged |= sliderDouble("elevation", mLightElevation, -10.0, 90.0, "%.0f deg");
    if (lightChanged) updateLight();
    sliderDouble("ambient", mScene.lighting.ambient, 0.0, 1.0, "%.2f");

    section("camera");
    ImGui::TextColored(kDimColor, "left drag: orbit    wheel: zoom");
    ImGui::TextColored(kDimColor, "right or middle drag, shift + left drag: pan");
    if (ImGui::Button("reset camera (R)")) resetCamera();
    ImGui::SameLine();
    ImGui::TextColored(kDimColor, "H: hide panels");

    savePanel();
    if (!mStatus.empty()) {
        ImGui::Separator();
        ImGui::PushTextWrapPos(0.0f);
        if (mStatusIsError)
            ImGui::TextColored(kErrorColor, "%s", mStatus.c_str());
        else
            ImGui::TextUnformatted(mStatus.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

void Viewer::reliefControls() {
    section("relief");
    ReliefSettings& relief = mScene.relief;
    // maxmip and cone need the baked depth's maximum mipmap or cone map: not offered while the material is
    // live. (The list follows the Technique enum; dual-depth textures are not the viewer's.)
    static const char* const kTechniques[] = {"texture", "normal", "parallax", "relief", "maxmip", "cone"};
    const bool live = mScene.meta == MetaPath::Live;
    if (ImGui::BeginCombo("technique", kTechniques[static_cast<int>(relief.technique)])) {
        for (int t = 0; t < static_cast<int>(std::size(kTechniques)); ++t) {
            const bool selected = t == static_cast<int>(relief.technique);
            const bool disabled = live && (static_cast<Technique>(t) == Technique::MaxMip ||
                                           static_cast<Technique>(t) == Technique::Cone);
            if (ImGui::Selectable(kTechniques[t], selected,
                                  disabled ? ImGuiSelectableFlags_Disabled : ImGuiSelectableFlags_None))
                relief.technique = static_cast<Technique>(t);
            if (disabled && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
                ImGui::SetTooltip("%s needs a baked material (Material panel: live off)", kTechniques[t]);
        }
        ImGui::EndCombo();
    }
    ImGui::BeginDisabled(relief.technique != Technique::Relief);
    ImGui::SliderInt("linear steps", &relief.linearSteps, 1, 256, "%d", ImGuiSliderFlags_Logarithmic);
    ImGui::SliderInt("binary steps", &relief.binarySteps, 0, 32);
    ImGui::EndDisabled();
    sliderDouble("depth scale S", mDepthScale, 0.005, 0.5, "%.3f", true);
    ImGui::SameLine();
    if (ImGui::SmallButton("S0")) mDepthScale = mMaterial.compose.depthScale;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("back to the material's S = %.3f", mMaterial.compose.depthScale);
    sliderDouble("tiling", relief.tiling, 0.25, 32.0, "%.2f", true);
    ImGui::Checkbox("self-shadowing", &relief.selfShadow);
    ImGui::Checkbox("depth correction", &relief.depthCorrection);

    section("ambient occlusion");
    ImGui::Checkbox("AO", &relief.ao);
    int rescale = relief.aoRescale == AoRescale::Paper ? 0 : relief.aoRescale == AoRescale::Exact ? 1 : 2;
    ImGui::BeginDisabled(!relief.ao);
    if (ImGui::Combo("AO rescale", &rescale, "paper (Eq. 6)\0exact (re-bake)\0off\0"))
        relief.aoRescale = rescale == 0 ? AoRescale::Paper : rescale == 1 ? AoRescale::Exact : AoRescale::Off;
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "How the AO baked at the material's S follows another depth scale:\n"
            "paper: the meta-relief paper's Eq. 4-6 per fragment; exact: re-baked at S;\n"
            "off: used as baked.");
}

void Viewer::gdmControls() {
    section("GDM");
    GdmViewSettings& gdm = mGdmSettings;
    static const char* const kTechniques[] = {"gdm", "refine", "march"};  // the GdmTechnique enum's order
    int technique = static_cast<int>(gdm.technique);
    if (ImGui::Combo("technique", &technique, kTechniques, static_cast<int>(std::size(kTechniques))))
        gdm.technique = static_cast<GdmTechnique>(technique);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "gdm: the paper's lookup, one GDM read per prism (Wang et al. 2004, Sec. 3.2)\n"
            "refine: exact steps on the asset's signed distance volume (beyond the paper)\n"
            "march: no GDM, the occupancy volume stepped every voxel (the slice-based baseline)");
    static const char* const kLightFrames[] = {"tangent (paper)", "jacobian"};  // GdmLightFrame's order
    int lightFrame = static_cast<int>(gdm.lightFrame);
    if (ImGui::Combo("light frame", &lightFrame, kLightFrames, static_cast<int>(std::size(kLightFrames))))
        gdm.lightFrame = static_cast<GdmLightFrame>(lightFrame);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "The shadow lookup's direction to the light in texture space:\n"
            "tangent: the direction in the surface's frame T, B, N (the paper's approximation)\n"
            "jacobian: mapped by each prism's own Jacobian");

    // Rank: the first K terms of the stored SVD (truncated on the worker, no re-bake), or the raw GDM.
    bool raw = gdm.rank == kGdmRankRaw;
    ImGui::BeginDisabled(raw);
    int rank = raw ? mGdmDescription.storedRank : gdm.rank;
    if (ImGui::SliderInt("rank", &rank, 1, mGdmDescription.storedRank, "%d", ImGuiSliderFlags_AlwaysClamp))
        gdm.rank = rank;
    ImGui::EndDisabled();
    if (mGdmDescription.hasRaw) {
        if (ImGui::Checkbox("raw GDM (no SVD)", &raw))
            gdm.rank = raw ? kGdmRankRaw : mGdmDescription.storedRank;
    } else {
        ImGui::TextColored(kDimColor, "no raw GDM in the asset (bake with --keep-raw)");
    }

    // T in world units; the default is H times the world length of one tile (it follows the tiling).
    const double defaultThickness = mGdm->asset.svd.height * mGdmShell.tileLength;
    double thickness = gdm.shellThickness.value_or(defaultThickness);
    if (defaultThickness > 0.0 &&
        sliderDouble("thickness T", thickness, defaultThickness / 8.0, defaultThickness * 4.0, "%.4f", true))
        gdm.shellThickness = thickness;
    ImGui::SameLine();
    if (ImGui::SmallButton("T0")) gdm.shellThickness.reset();
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("back to H x tile length = %.3g x %.4f = %.4f", mGdm->asset.svd.height,
                          mGdmShell.tileLength, defaultThickness);
    sliderDouble("tiling", gdm.tiling, 0.25, 32.0, "%.2f", true);
    if (hasEnvironment(*mGdm)) environmentControls();

    static const int kSamples[] = {1, 4, 9, 16};
    int samples = 0;
    while (samples < 3 && kSamples[samples] != mGdmSamples) ++samples;
    if (ImGui::Combo("samples", &samples,
                     "1\0"
                     "4 (2 x 2)\0"
                     "9 (3 x 3)\0"
                     "16 (4 x 4)\0"))
        mGdmSamples = kSamples[samples];
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("per pixel, supersampled as strata render --samples (each costs a whole picture)");
    int preview = mGdmPreview == 1 ? 0 : mGdmPreview == 2 ? 1 : 2;
    if (ImGui::Combo("while moving", &preview,
                     "full size\0"
                     "1/2 size\0"
                     "1/4 size\0"))
        mGdmPreview = preview == 0 ? 1 : preview == 1 ? 2 : 4;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "While the view or a setting changes, draw smaller pictures (one sample per pixel):\n"
            "a GDM picture is drawn offscreen and read back, seconds per frame on llvmpipe.");
}

void Viewer::environmentControls() {
    // Live: a rotation or an intensity sets the turned environment alone (GdmView::render), no re-bake.
    section("environment");
    ImGui::TextUnformatted(mGdmDescription.environment.c_str());
    GdmViewSettings& gdm = mGdmSettings;
    sliderDouble("rotation", gdm.environmentRotation, -180.0, 180.0, "%.1f deg");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Degrees the environment turns about +z (towards +y), as strata render --env-rotation");
    sliderDouble("intensity", gdm.environmentIntensity, 0.0, 4.0, "%.2f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Its radiance's scale, as strata render --env-intensity");
    ImGui::SameLine();
    if (ImGui::SmallButton("E0")) {
        gdm.environmentRotation = mScene.environment.rotation;
        gdm.environmentIntensity = mScene.environment.intensity;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("back to the scene's rotation %.1f and intensity %.2f", mScene.environment.rotation,
                          mScene.environment.intensity);
    // The RTV was baked when the GDM was loaded: its bounces and rank need a bake (--env-bounces,
    // --env-rank).
    ImGui::TextColored(kDimColor, "RTV: %d bounce%s, rank %d (read-only)", mScene.environment.bounces,
                       mScene.environment.bounces == 1 ? "" : "s", mGdmDescription.rtvRank);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Baked into the radiance transfer volume when the GDM was loaded: changing them needs a bake.\n"
            "Start the viewer again with --env-bounces / --env-rank (or the scene's env_bounces, env_rank).");
}

void Viewer::gdmPanel() {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkSize.x - kPanelWidth - kMargin, kMargin),
                            ImGuiCond_FirstUseEver);
    // Text only: it fits its lines, which change (the picture's, the drawing one).
    if (!ImGui::Begin("GDM", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::End();
        return;
    }
    const GdmDescription& d = mGdmDescription;
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + kPanelWidth - 16.0f);
    ImGui::TextUnformatted(d.source.c_str());
    ImGui::TextColored(kDimColor, "%s", d.dims.c_str());
    ImGui::TextColored(kDimColor, "H = %.3g tile widths", d.height);
    const int rank = mGdmSettings.rank;
    if (rank == kGdmRankRaw) {
        ImGui::Text("raw GDM: %.1f MiB", d.rawMiB);
    } else {
        // W (rows x K) and E (K x cols) are both linear in K.
        ImGui::Text("rank %d of %d: %.2f MiB (stored %.2f MiB)", rank, d.storedRank,
                    d.svdMiB * rank / d.storedRank, d.svdMiB);
    }
    if (d.hasRaw && rank != kGdmRankRaw) ImGui::TextColored(kDimColor, "raw GDM: %.1f MiB", d.rawMiB);
    ImGui::TextColored(kDimColor, "volumes (occupancy, albedo): %.2f MiB", d.volumeMiB);
    if (!d.environment.empty()) {
        section("environment");
        ImGui::TextUnformatted(d.environment.c_str());
        ImGui::TextColored(kDimColor, "RTV rank %d, %d bounce%s: %.2f MiB", d.rtvRank,
                           mScene.environment.bounces, mScene.environment.bounces == 1 ? "" : "s", d.rtvMiB);
        ImGui::TextColored(kDimColor, "turned %.1f deg, intensity %.2f", mGdmSettings.environmentRotation,
                           mGdmSettings.environmentIntensity);
    }
    section("shell");
    ImGui::Text("T = %.4f world units, %zu prisms", mGdmShell.thickness, mGdmShell.prisms.size());
    ImGui::TextColored(kDimColor, "tile length %.4f at tiling %.2f", mGdmShell.tileLength,
                       mGdmSettings.tiling);
    section("picture");
    if (mGdmShown)
        ImGui::Text("%dx%d, %d sample%s: %.0f ms", mGdmShown->width, mGdmShown->height, mGdmShown->samples,
                    mGdmShown->samples > 1 ? "s" : "", mGdmPictureMs);
    if (mGdmWorker->busy())
        ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.4f, 1.0f), "drawing %dx%d ...",
                           mGdmSubmitted ? mGdmSubmitted->width : 0,
                           mGdmSubmitted ? mGdmSubmitted->height : 0);
    ImGui::TextColored(kDimColor, "drawn offscreen on a worker thread and read back");
    ImGui::PopTextWrapPos();
    ImGui::End();
}

void Viewer::savePanel() {
    section("save");
    if (!mGdm) materialSaveControls();
    ImGui::InputText("##screenshotpath", &mScreenshotPath);
    ImGui::SameLine();
    if (ImGui::Button("screenshot (S)")) mCaptureRequested = true;
    ImGui::Checkbox("screenshot with panels", &mScreenshotWithUi);
}

void Viewer::materialSaveControls() {
    ImGui::InputText("##materialpath", &mMaterialPath);
    ImGui::SameLine();
    if (ImGui::Button("save material")) {
        try {
            const fs::path path(mMaterialPath);
            std::vector<fs::path> others;
            if (fs::exists(mMesh.name)) others.push_back(mMesh.name);
            if (!mOptions.sceneFile.empty()) others.push_back(mOptions.sceneFile);
            refuseToOverwriteInputs(path, others);
            saveMaterial(mMaterial, path);
            setStatus("wrote " + mMaterialPath, false);
        } catch (const Error& e) {
            setStatus(e.what(), true);
        }
    }
}

void Viewer::materialPanel() {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkSize.x - kPanelWidth - kMargin, kMargin),
                            ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(kPanelWidth, 0.0f), ImGuiCond_FirstUseEver);
    fitToWindow();
    if (!ImGui::Begin("Material")) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(-120.0f);

    int removeIndex = -1, moveFrom = -1, moveTo = -1;
    for (int i = 0; i < static_cast<int>(mMaterial.layers.size()); ++i)
        layerControls(i, removeIndex, moveFrom, moveTo);
    // Structural edits after the loop, so that it never walks a list that changed under it.
    if (removeIndex >= 0) removeLayer(mMaterial, removeIndex);
    if (moveFrom >= 0) moveLayer(mMaterial, moveFrom, moveTo);

    addLayerControls();

    section("composition");
    bool live = mScene.meta == MetaPath::Live;
    if (ImGui::Checkbox("live (per fragment)", &live)) {
        mScene.meta = live ? MetaPath::Live : MetaPath::Baked;
        if (live &&
            (mScene.relief.technique == Technique::MaxMip || mScene.relief.technique == Technique::Cone)) {
            setStatus(std::string(toString(mScene.relief.technique)) +
                          " needs a baked material: technique set to relief",
                      false);
            mScene.relief.technique = Technique::Relief;
        }
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "live: the layers go to the GPU as they are and the shader combines them per fragment;\n"
            "weights and tilings change at once, with no composition (docs/live-meta-relief.md).\n"
            "baked: composed on the CPU at %d^2 after every change.",
            mOptions.resolution);
    int normals = mMaterial.compose.normals == NormalMode::Paper ? 0 : 1;
    if (ImGui::Combo("normals", &normals, "paper (Eq. 1)\0consistent\0"))
        mMaterial.compose.normals = normals == 0 ? NormalMode::Paper : NormalMode::Consistent;
    int ao = !mMaterial.ao ? 3 : static_cast<int>(*mMaterial.ao);
    if (ImGui::Combo("material AO", &ao, "exact\0multiply\0min\0none\0")) {
        if (ao == 3)
            mMaterial.ao.reset();
        else
            mMaterial.ao = static_cast<MetaAoMode>(ao);
    }

    // What the pipeline is doing: the bake runs on a worker thread, the window keeps the last result.
    ImGui::Separator();
    ImGui::PushTextWrapPos(0.0f);
    if (mPipeline.busy())
        ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.4f, 1.0f), "%s ...", mPipeline.activity().c_str());
    if (!mPipeline.error().empty()) {
        ImGui::TextColored(kErrorColor, "%s", mPipeline.error().c_str());
    } else if (live) {
        const BakeResult& bake = mPipeline.lastBake();
        ImGui::TextColored(kDimColor, "live: upload %.0f ms (load %.0f); weights %.2f ms",
                           mPipeline.lastUploadSeconds() * 1e3, bake.loadSeconds * 1e3,
                           mPipeline.lastSetLayerSeconds() * 1e3);
        if (mMaterial.ao == MetaAoMode::Exact)
            ImGui::TextColored(kDimColor, "composed AO %d^2: %.0f ms (compose %.0f, AO %.0f)",
                               mOptions.resolution, mPipeline.lastSeconds() * 1e3, bake.composeSeconds * 1e3,
                               bake.aoSeconds * 1e3);
        for (const std::string& note : bake.notes) ImGui::TextColored(kDimColor, "note: %s", note.c_str());
    } else if (!mPipeline.busy()) {
        const BakeResult& bake = mPipeline.lastBake();
        ImGui::TextColored(kDimColor, "%d^2: %.0f ms (load %.0f, compose %.0f, AO %.0f)", mOptions.resolution,
                           mPipeline.lastSeconds() * 1e3, bake.loadSeconds * 1e3, bake.composeSeconds * 1e3,
                           bake.aoSeconds * 1e3);
        for (const std::string& note : bake.notes) ImGui::TextColored(kDimColor, "note: %s", note.c_str());
    }
    ImGui::PopTextWrapPos();
    ImGui::PopItemWidth();
    ImGui::End();
}

void Viewer::layerControls(int index, int& removeIndex, int& moveFrom, int& moveTo) {
    MaterialLayer& layer = mMaterial.layers[static_cast<std::size_t>(index)];
    const int count = static_cast<int>(mMaterial.layers.size());
    ImGui::PushID(index);
    const bool open =
        ImGui::CollapsingHeader(layerTitle(layer, index).c_str(), ImGuiTreeNodeFlags_DefaultOpen);
    // Order and removal on the header's line.
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 70.0f);
    ImGui::BeginDisabled(index == 0);
    if (ImGui::ArrowButton("up", ImGuiDir_Up)) moveFrom = index, moveTo = index - 1;
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(index == count - 1);
    if (ImGui::ArrowButton("down", ImGuiDir_Down)) moveFrom = index, moveTo = index + 1;
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(count == 1);
    if (ImGui::SmallButton("x")) removeIndex = index;
    ImGui::EndDisabled();
    if (open) {
        sliderDouble("depth weight", layer.weightDepth, 0.0, 2.0, "%.3f");
        sliderDouble("normal weight", layer.weightNormal, 0.0, 2.0, "%.3f");
        sliderDouble("layer tiling", layer.tiling, 0.25, 64.0, "%.2f", true);
        if (layer.pattern) {
            const std::uint32_t step = 1;
            ImGui::InputScalar("seed", ImGuiDataType_U32, &layer.patternParams.seed, &step);
            int sizeLog = static_cast<int>(std::lround(std::log2(layer.patternParams.size)));
            if (ImGui::SliderInt("size", &sizeLog, 6, 11, "")) layer.patternParams.size = 1 << sizeLog;
            ImGui::SameLine(0.0f, 0.0f);
            ImGui::TextColored(kDimColor, " %d^2", layer.patternParams.size);
        } else {
            const fs::path& file = layer.depthFile ? *layer.depthFile : *layer.heightFile;
            ImGui::TextColored(kDimColor, "%s %s", layer.depthFile ? "depth" : "height",
                               file.string().c_str());
            if (layer.normalFile) normalYControl(layer);
        }
        if (hasColor(layer)) {
            if (ImGui::RadioButton("colour from this layer", mMaterial.compose.colorFrom == index))
                mMaterial.compose.colorFrom = index;
        }
    }
    ImGui::PopID();
}

// The green channel of a layer's normal map ("normal_y" in the material): auto detects it from the layer's
// depth when the layer is read, as `strata import` does; up or down says it. A change re-reads the layer,
// and an explicit choice that the depth's gradient clearly contradicts is reported in the status line.
void Viewer::normalYControl(MaterialLayer& layer) {
    int normalY = layer.normalYAuto ? 0 : layer.normalYDown ? 2 : 1;
    if (ImGui::Combo("normal y", &normalY, "auto (from depth)\0up (OpenGL)\0down (DirectX)\0")) {
        layer.normalYAuto = normalY == 0;
        layer.normalYDown = normalY == 2;
    }
}

void Viewer::addLayerControls() {
    section("add a layer");
    static const std::vector<std::string> names = patternNames();
    comboNames("pattern", names, mAddPattern);
    ImGui::InputInt("seed##add", &mAddSeed);
    mAddSeed = std::max(mAddSeed, 0);
    if (ImGui::Button("add pattern layer")) {
        MaterialLayer layer = patternLayer(mAddPattern, 512, static_cast<std::uint32_t>(mAddSeed));
        // A new detail layer starts fine and light, like the paper's examples (fabric at 8, weight 0.3).
        layer.tiling = 4.0;
        layer.weightDepth = 0.3;
        layer.weightNormal = 0.3;
        addLayer(mMaterial, std::move(layer));
    }
    ImGui::InputTextWithHint("depth / height", "file (0 = top) or texture set dir", &mAddDepthFile);
    ImGui::Checkbox("height map (white = high)", &mAddIsHeight);
    ImGui::InputTextWithHint("normal", "optional", &mAddNormalFile);
    ImGui::Combo("normal y##add", &mAddNormalY, "auto (from depth)\0up (OpenGL)\0down (DirectX)\0");
    ImGui::InputTextWithHint("colour", "optional", &mAddColorFile);
    if (ImGui::Button("add file layer")) {
        try {
            MaterialLayer layer;
            if (fs::is_directory(mAddDepthFile)) {
                layer = openMaterial(mAddDepthFile).layers.front();  // a texture set: its maps
            } else {
                layer = fileLayer(mAddDepthFile, mAddIsHeight, mAddNormalFile, mAddColorFile);
                layer.normalYAuto = mAddNormalY == 0;
                layer.normalYDown = mAddNormalY == 2;
            }
            // Read it now, so that a bad file is reported here and never enters the material.
            Material single;
            single.compose = mMaterial.compose;
            single.layers = {layer};
            loadLayers(single);
            addLayer(mMaterial, std::move(layer));
            setStatus("added " + mAddDepthFile, false);
        } catch (const Error& e) {
            setStatus(e.what(), true);
        }
    }
}

void Viewer::statsOverlay() {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + viewport->WorkSize.x * 0.5f,
                                   viewport->WorkPos.y + viewport->WorkSize.y - kMargin),
                            ImGuiCond_Always, ImVec2(0.5f, 1.0f));
    ImGui::SetNextWindowBgAlpha(0.55f);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove;
    if (ImGui::Begin("frame time", nullptr, flags)) {
        const double frameMs = mFrameMs.mean();
        // In GDM mode the scene's time is the last picture's on the worker (the window's frames only show
        // it).
        ImGui::Text("frame %.1f ms (%.1f fps)  %s %.1f ms  %dx%d  %s", frameMs,
                    frameMs > 0.0 ? 1000.0 / frameMs : 0.0, mGdm ? "GDM picture" : "scene",
                    mGdm ? mGdmPictureMs : mSceneMs.mean(), static_cast<int>(viewport->WorkSize.x),
                    static_cast<int>(viewport->WorkSize.y), mRendererName.c_str());
    }
    ImGui::End();
}

}  // namespace strata::view
