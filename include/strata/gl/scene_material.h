// A scene's material in GPU memory: the one upload that `strata render`, `strata compare`, the viewer and the
// tests share. strata/scene/scene_material.h makes the CPU side (prepareSceneMaterial); this uploads it.
#pragma once

#include "strata/gl/gpu_material.h"
#include "strata/scene/scene_material.h"

namespace strata::gl {

// Uploads `material` by its kind: Baked with uploadMaterial(texture, aoDepthScale); Live with
// uploadLiveMaterial(layers, compose, liveAo, aoParams, layerAo), then setComposedAo(composedAo,
// composedAoDepthScale) when it has a composed AO map; DualDepth with uploadDualDepth(dual). Needs a current
// GL 4.5 core context; throws like those functions.
GpuMaterial uploadSceneMaterial(const SceneMaterial& material);

}  // namespace strata::gl
