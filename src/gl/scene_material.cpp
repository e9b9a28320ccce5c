#include "strata/gl/scene_material.h"

namespace strata::gl {

GpuMaterial uploadSceneMaterial(const SceneMaterial& material) {
    switch (material.kind) {
        case MaterialKind::Live: {
            GpuMaterial gpu = uploadLiveMaterial(material.layers, material.compose, material.liveAo,
                                                 material.aoParams, material.layerAo);
            if (!material.composedAo.empty())
                gpu.setComposedAo(material.composedAo, material.composedAoDepthScale);
            return gpu;
        }
        case MaterialKind::DualDepth:
            return uploadDualDepth(material.dual);
        case MaterialKind::Baked:
            break;
    }
    return uploadMaterial(material.texture, material.aoDepthScale);
}

}  // namespace strata::gl
