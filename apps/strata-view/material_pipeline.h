// "The material changed -> the GPU material the renderer draws", in one place: MaterialPipeline::update.
//
// Two paths, by BakeRequest::meta (`--meta`, the Material panel's "live (per fragment)"):
//
//   baked  a change composes the meta-relief on the CPU and bakes its AO (MaterialBaker), then uploads the
//          result (gl::uploadMaterial);
//   live   the loaded layers are uploaded as they are (gl::uploadLiveMaterial) and the shader combines them
//          per fragment. Weights and tilings are uniforms (GpuMaterial::setLayer, on the calling thread,
//          no worker); only a change of the layer list (add, remove, reorder, seed, size, files), the
//          normal mode, the colour layer or the AO settings uploads again. With material AO "exact" the AO
//          map of the composed depth is baked on the worker (MaterialBaker::bake) and handed over with
//          GpuMaterial::setComposedAo; a weight change re-bakes it in the background, the previous map is
//          shown until then.
//
// The CPU work (loading layers, composing, baking AO) runs on a worker thread, so the window keeps drawing
// (with the previous material) while it works; edits made meanwhile are coalesced into one job for the
// latest state. GL calls stay on the caller's thread. A job hands back a strata::SceneMaterial (the per-layer
// AO maps of material AO "multiply" or "min" baked on the worker by liveLayerAo), and the caller's thread
// uploads it with gl::uploadSceneMaterial, as `strata render` does.
#pragma once

#include "material_bake.h"

#include "strata/gl/gpu_material.h"
#include "strata/scene/scene_material.h"

#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

namespace strata::view {

class MaterialPipeline {
public:
    MaterialPipeline();
    // Waits for a job in flight. Needs the GL context that uploaded the material to be current.
    ~MaterialPipeline();
    MaterialPipeline(const MaterialPipeline&) = delete;
    MaterialPipeline& operator=(const MaterialPipeline&) = delete;

    // Call once per frame with the current state, on the thread whose GL context is current. Starts a job
    // when the state differs from the last one submitted (and none is running); uploads a finished one; in
    // live mode applies weights and tilings to the uploaded material at once. Cheap when nothing changed
    // (it compares key strings). Returns the material to draw: the last successful upload's, null before
    // the first has finished. A failure keeps the previous material and sets error().
    const gl::GpuMaterial* update(const BakeRequest& request);

    // update() until nothing is left to do for `request`, waiting for the jobs and uploading their results.
    // Rethrows a failure (the library's Error, with its kind): for start-up and --screenshot, where there
    // is nothing to show without it.
    const gl::GpuMaterial* updateAndWait(const BakeRequest& request);

    bool busy() const { return mJob.valid(); }
    // What the running job does ("composing", "loading layers", "baking the composed AO"); "" when idle.
    const std::string& activity() const { return mActivity; }
    // Why the last job or the last live weight change failed, "" after a success.
    const std::string& error() const { return mLayerError.empty() ? mError : mLayerError; }
    // The last successful job's report (timings, notes). In live mode: its layer loading and, with
    // material AO "exact", the composition and AO bake behind the composed AO map.
    const BakeResult& lastBake() const { return mLastBake; }
    // Wall time of the last successful job, upload included.
    double lastSeconds() const { return mLastSeconds; }
    // Seconds the last live upload took on the caller's thread (uploadLiveMaterial, with its layer AO).
    double lastUploadSeconds() const { return mLastUploadSeconds; }
    // Seconds the last live weight / tiling change took (setLayer on every changed layer).
    double lastSetLayerSeconds() const { return mLastSetLayerSeconds; }
    // Counters, for tests and the panel: worker jobs started, materials uploaded (uploadMaterial or
    // uploadLiveMaterial), live weight changes applied with setLayer, composed AO maps set.
    int jobsStarted() const { return mJobsStarted; }
    int uploads() const { return mUploads; }
    int layerUpdates() const { return mLayerUpdates; }
    int composedAoUpdates() const { return mComposedAoUpdates; }

private:
    // What a worker job hands back.
    struct Work {
        bool upload = true;         // upload `material` (live: false when only its composed AO changed)
        SceneMaterial material;     // what to upload: baked (the texture) or live (the layers, their AO)
        std::string liveKey;        // live: the structure the job is for
        std::string composedAoKey;  // live: what material.composedAo was baked for, "" if the job made none
        BakeResult bake;            // the report (its texture moved into `material`)
    };

    const gl::GpuMaterial* updateLive(const BakeRequest& request);
    void applyLayers(const BakeRequest& request);
    void start(std::string key, std::string activity, std::function<Work()> job);
    void collect();

    MaterialBaker mBaker;  // used by the worker only, one job at a time
    std::future<Work> mJob;
    std::string mSubmittedKey;
    std::string mActivity;
    std::chrono::steady_clock::time_point mJobStart;
    std::unique_ptr<gl::GpuMaterial> mGpu;
    std::string mLiveKey;        // the structure of mGpu when it is live, "" otherwise
    std::string mComposedAoKey;  // what mGpu's composed AO map was baked for, "" for none
    std::string mError;
    std::string mLayerError;
    std::exception_ptr mFailure;
    BakeResult mLastBake;
    double mLastSeconds = 0.0;
    double mLastUploadSeconds = 0.0;
    double mLastSetLayerSeconds = 0.0;
    int mJobsStarted = 0;
    int mUploads = 0;
    int mLayerUpdates = 0;
    int mComposedAoUpdates = 0;
};

}  // namespace strata::view
