#include "material_pipeline.h"

#include "strata/core/error.h"

#include <chrono>

namespace strata::view {

MaterialPipeline::MaterialPipeline() = default;

MaterialPipeline::~MaterialPipeline() {
    if (mJob.valid()) mJob.wait();
}

const gl::GpuMaterial* MaterialPipeline::update(const BakeRequest& request) {
    if (mJob.valid() && mJob.wait_for(std::chrono::seconds(0)) == std::future_status::ready) collect();
    if (!mJob.valid()) {
        std::string key = bakeKey(request);
        if (key != mSubmittedKey) {
            mSubmittedKey = std::move(key);
            mJobStart = std::chrono::steady_clock::now();
            // The request is copied: the caller keeps editing its own while the worker bakes this one.
            mJob = std::async(std::launch::async, [this, request] { return mBaker.bake(request); });
        }
    }
    return mGpu.get();
}

const gl::GpuMaterial* MaterialPipeline::updateAndWait(const BakeRequest& request) {
    update(request);
    if (mJob.valid()) {
        mJob.wait();
        collect();
    }
    // The request may have been submitted by an earlier update() whose bake failed.
    if (mFailure) std::rethrow_exception(mFailure);
    return mGpu.get();
}

void MaterialPipeline::collect() {
    try {
        BakeResult result = mJob.get();
        // The texture goes to the GPU as it is; the CPU copy is not kept (the baker caches what it needs).
        auto gpu = std::make_unique<gl::GpuMaterial>(gl::uploadMaterial(result.texture, result.aoDepthScale));
        result.texture = {};
        mGpu = std::move(gpu);
        mLastBake = std::move(result);
        mLastSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - mJobStart).count();
        mError.clear();
        mFailure = nullptr;
    } catch (const std::exception& e) {
        mError = e.what();
        mFailure = std::current_exception();
    }
}

}  // namespace strata::view
