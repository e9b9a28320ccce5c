#include "material_pipeline.h"

#include "material_document.h"

#include "strata/core/error.h"
#include "strata/gl/scene_material.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/occlusion/meta_relief_ao.h"

#include <nlohmann/json.hpp>

#include <chrono>

namespace strata::view {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool layerAoAtUpload(const Material& material) {
    return material.ao == MetaAoMode::Multiply || material.ao == MetaAoMode::Min;
}

// What a live upload depends on: the material without its layers' tilings and weights (setLayer changes
// those) and without the composition size (not used live). With per-layer AO ("multiply", "min") a layer
// whose depth weight is 0 at upload gets no AO map (uploadLiveMaterial skips it), so crossing 0 uploads
// again.
std::string liveKey(const BakeRequest& request) {
    Material material = request.material;
    material.compose.resolution = kDefaultEditResolution;
    const bool layerAo = layerAoAtUpload(material);
    for (MaterialLayer& layer : material.layers) {
        layer.tiling = 1.0;
        layer.weightDepth = !layerAo || layer.weightDepth > 0.0 ? 1.0 : 0.0;
        layer.weightNormal = 1.0;
    }
    return materialToJson(material, "/").dump();
}

}  // namespace

MaterialPipeline::MaterialPipeline() = default;

MaterialPipeline::~MaterialPipeline() {
    if (mJob.valid()) mJob.wait();
}

void MaterialPipeline::start(std::string key, std::string activity, std::function<Work()> job) {
    mSubmittedKey = std::move(key);
    mActivity = std::move(activity);
    mJobStart = std::chrono::steady_clock::now();
    ++mJobsStarted;
    mJob = std::async(std::launch::async, std::move(job));
}

const gl::GpuMaterial* MaterialPipeline::update(const BakeRequest& request) {
    if (mJob.valid() && mJob.wait_for(std::chrono::seconds(0)) == std::future_status::ready) collect();
    if (request.meta == MetaPath::Live) return updateLive(request);
    mLayerError.clear();
    if (!mJob.valid()) {
        std::string key = bakeKey(request);
        if (key != mSubmittedKey) {
            // The request is copied: the caller keeps editing its own while the worker bakes this one.
            start(std::move(key), "composing", [this, request] {
                Work work;
                work.bake = mBaker.bake(request);
                work.material.kind = MaterialKind::Baked;
                work.material.depthScale = request.renderDepthScale;
                work.material.texture = std::move(work.bake.texture);
                work.material.aoDepthScale = work.bake.aoDepthScale;
                return work;
            });
        }
    }
    return mGpu.get();
}

const gl::GpuMaterial* MaterialPipeline::updateLive(const BakeRequest& request) {
    const std::string structure = liveKey(request);
    const bool exactAo = request.material.ao == MetaAoMode::Exact;
    const std::string aoKey = exactAo ? bakeKey(request) : std::string();
    const bool uploaded = mGpu && mGpu->isLive() && mLiveKey == structure;
    // Weights and tilings: uniforms, now.
    if (uploaded) applyLayers(request);
    if (!mJob.valid()) {
        const bool needUpload = !uploaded;
        const bool needAo = exactAo && (needUpload || mComposedAoKey != aoKey);
        std::string key = "live " + structure + " ao " + aoKey;
        if ((needUpload || needAo) && key != mSubmittedKey) {
            const char* activity = needUpload ? "loading layers" : "baking the composed AO";
            start(std::move(key), activity, [this, request, structure, needUpload, needAo, aoKey] {
                Work work;
                work.upload = needUpload;
                work.liveKey = structure;
                SceneMaterial& material = work.material;
                material.kind = MaterialKind::Live;
                material.depthScale = request.renderDepthScale;
                material.compose = request.material.compose;
                material.liveAo = request.material.ao;
                material.aoParams = request.material.aoParams;
                if (needUpload) {
                    material.layers = mBaker.layers(request, work.bake);
                    // The layers' AO maps here on the worker, so that the GL thread only uploads.
                    const auto start = std::chrono::steady_clock::now();
                    material.layerAo =
                        liveLayerAo(material.layers, material.compose, material.liveAo, material.aoParams);
                    work.bake.aoSeconds += secondsSince(start);
                }
                if (needAo) {
                    // The composition and its exact AO (at the render's S with AoRescale::Exact), as the
                    // baked path makes them; the layers come from the cache filled above.
                    BakeResult bake = mBaker.bake(request);
                    bake.layersLoaded += work.bake.layersLoaded;
                    bake.loadSeconds += work.bake.loadSeconds;
                    bake.notes.insert(bake.notes.begin(), work.bake.notes.begin(), work.bake.notes.end());
                    work.bake = std::move(bake);
                    material.composedAo = std::move(work.bake.texture.ao);
                    material.composedAoDepthScale = work.bake.aoDepthScale;
                    work.composedAoKey = aoKey;
                }
                return work;
            });
        }
    }
    return mGpu.get();
}

void MaterialPipeline::applyLayers(const BakeRequest& request) {
    const std::vector<MaterialLayer>& layers = request.material.layers;
    const std::vector<gl::GpuLayer>& gpuLayers = mGpu->layers();
    if (layers.size() != gpuLayers.size()) return;  // cannot happen: the layer count is in the live key
    std::vector<int> pending;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        if (layers[i].tiling != gpuLayers[i].tiling || layers[i].weightDepth != gpuLayers[i].weightDepth ||
            layers[i].weightNormal != gpuLayers[i].weightNormal)
            pending.push_back(static_cast<int>(i));
    }
    if (pending.empty()) {
        mLayerError.clear();
        return;
    }
    // setLayer checks the sums after each layer: a change that moves weight from one layer to another may
    // pass only in one order, so a layer refused is tried again after the others.
    const auto start = std::chrono::steady_clock::now();
    std::string message;
    while (!pending.empty()) {
        std::vector<int> refused;
        for (int i : pending) {
            const MaterialLayer& layer = layers[static_cast<std::size_t>(i)];
            try {
                mGpu->setLayer(i, layer.tiling, layer.weightDepth, layer.weightNormal);
            } catch (const Error& e) {
                refused.push_back(i);
                message = e.what();
            }
        }
        if (refused.size() == pending.size()) break;
        pending = std::move(refused);
    }
    if (pending.empty()) {
        mLayerError.clear();
        ++mLayerUpdates;
        mLastSetLayerSeconds = secondsSince(start);
    } else {
        mLayerError = message;  // the material keeps the last valid weights
    }
}

const gl::GpuMaterial* MaterialPipeline::updateAndWait(const BakeRequest& request) {
    // A job may leave more to do (a live upload followed by its weights); each round submits at most one.
    for (;;) {
        update(request);
        if (!mJob.valid()) break;
        mJob.wait();
        collect();
    }
    // The request may have been submitted by an earlier update() whose job failed.
    if (mFailure) std::rethrow_exception(mFailure);
    return mGpu.get();
}

void MaterialPipeline::collect() {
    mActivity.clear();
    try {
        Work work = mJob.get();
        const bool live = work.material.kind == MaterialKind::Live;
        const bool composedAo = !work.composedAoKey.empty();
        bool aoApplied = false;
        if (work.upload) {
            // GL, so here on the context's thread; everything on the CPU was made on the worker. The CPU copy
            // is not kept (the baker caches what it needs).
            const auto start = std::chrono::steady_clock::now();
            mGpu = std::make_unique<gl::GpuMaterial>(gl::uploadSceneMaterial(work.material));
            mLiveKey = live ? work.liveKey : std::string();
            mComposedAoKey.clear();
            aoApplied = composedAo;
            if (live) mLastUploadSeconds = secondsSince(start);
            ++mUploads;
        } else if (composedAo && mGpu && mGpu->isLive() && mLiveKey == work.liveKey) {
            mGpu->setComposedAo(work.material.composedAo, work.material.composedAoDepthScale);
            aoApplied = true;
        }
        if (aoApplied) {
            mComposedAoKey = work.composedAoKey;
            ++mComposedAoUpdates;
        }
        work.bake.texture = {};
        mLastBake = std::move(work.bake);
        mLastSeconds = secondsSince(mJobStart);
        mError.clear();
        mFailure = nullptr;
    } catch (const std::exception& e) {
        mError = e.what();
        mFailure = std::current_exception();
    }
}

}  // namespace strata::view
