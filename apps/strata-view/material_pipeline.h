// "The material changed -> the GPU material the renderer draws", in one place: MaterialPipeline::update.
//
// Today a change means composing the meta-relief on the CPU and baking its AO (MaterialBaker), then
// uploading the result (gl::uploadMaterial). That runs on a worker thread, so the window keeps drawing (with
// the previous material) while it works; edits made meanwhile are coalesced into one bake of the latest
// state. The live meta-relief path (the layers sampled per fragment by the shader) replaces the body of
// update(): upload each layer once, then weights, tiling and order become uniforms and nothing is baked.
// Nothing else in the viewer knows how a material reaches the GPU.
#pragma once

#include "material_bake.h"

#include "strata/gl/relief_renderer.h"

#include <exception>
#include <future>
#include <memory>
#include <string>
#include <vector>

namespace strata::view {

class MaterialPipeline {
public:
    MaterialPipeline();
    // Waits for a bake in flight. Needs the GL context that uploaded the material to be current.
    ~MaterialPipeline();
    MaterialPipeline(const MaterialPipeline&) = delete;
    MaterialPipeline& operator=(const MaterialPipeline&) = delete;

    // Call once per frame with the current state, on the thread whose GL context is current. Starts a bake
    // when the state differs from the last one submitted (and none is running); uploads a finished bake.
    // Cheap when nothing changed (it compares bakeKey strings). Returns the material to draw: the last
    // successful bake's, null before the first has finished. A failed bake keeps the previous material and
    // sets error().
    const gl::GpuMaterial* update(const BakeRequest& request);

    // update(), then waits for the bake of `request` to finish and uploads it. Rethrows its failure (the
    // library's Error, with its kind): for start-up and --screenshot, where there is nothing to show
    // without it.
    const gl::GpuMaterial* updateAndWait(const BakeRequest& request);

    bool busy() const { return mJob.valid(); }
    // The last bake's failure message, "" after a success.
    const std::string& error() const { return mError; }
    // The last successful bake's report (timings, notes).
    const BakeResult& lastBake() const { return mLastBake; }
    // Wall time of the last successful bake, upload included.
    double lastSeconds() const { return mLastSeconds; }

private:
    void collect();

    MaterialBaker mBaker;  // used by the worker only, one bake at a time
    std::future<BakeResult> mJob;
    std::string mSubmittedKey;
    std::chrono::steady_clock::time_point mJobStart;
    std::unique_ptr<gl::GpuMaterial> mGpu;
    std::string mError;
    std::exception_ptr mFailure;
    BakeResult mLastBake;
    double mLastSeconds = 0.0;
};

}  // namespace strata::view
