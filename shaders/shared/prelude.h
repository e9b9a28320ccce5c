// What every shared GLSL/C++ header (shaders/shared/*.h) needs, written once (STYLE.md, "GLSL beside C++";
// the model is Falcor's HostDeviceShared.slangh). A shared header reads:
//
//     #ifdef __cplusplus
//     #pragma once
//     #endif
//     #include "prelude.h"
//     STRATA_SHARED_BEGIN
//     STRATA_SHARED_FUNCTION float f(vec2 x) { ... }   // GLSL 4.50 that is also C++ with glm
//     STRATA_SHARED_END
//
// C++ gets the functions in namespace strata::shared, inline, with the GLSL names they use (vec2, floor,
// mix, ...) taken from glm there; GLSL gets them as written. Literals carry the f suffix, so that C++
// computes in float as the shader does.
//
// A loop whose texture reads the includer supplies (shared/relief_search.h, maxmip.h, cone.h) is written
// between STRATA_SHARED_CLASS_BEGIN(Name) and STRATA_SHARED_CLASS_END, its fetches declared with
// STRATA_SHARED_FETCH(signature):
//   - GLSL: the class markers vanish and each fetch is a prototype; the shader defines the function
//     (before or after the include), reading its textures and uniforms;
//   - C++: Name is a class whose fetches are pure virtual member functions and whose loops are member
//     functions; a derived class supplies the fetches (e.g. strata/trace/shader_loops.h reads Images and
//     counts the fetches).
//
// The shader library pastes each file once per stage (src/gl/program.cpp), so this file is pasted before the
// first shared header only: it defines macros and nothing that a second paste would need. C++ reads it once
// (#pragma once); the macros stay defined for every later header.
#ifdef __cplusplus
#pragma once
#include <glm/glm.hpp>

namespace strata::shared {
// The GLSL types and built-in functions the shared headers use.
using glm::bvec2;
using glm::ivec2;
using glm::ivec3;
using glm::vec2;
using glm::vec3;
using glm::vec4;

using glm::abs;
using glm::acos;
using glm::any;
using glm::atan;
using glm::ceil;
using glm::clamp;
using glm::cos;
using glm::dot;
using glm::exp2;
using glm::floor;
using glm::greaterThan;
using glm::length;
using glm::lessThan;
using glm::log2;
using glm::max;
using glm::min;
using glm::mix;
using glm::sign;
using glm::sqrt;
using glm::step;
}  // namespace strata::shared

// One macro per line reads better than clang-format's backslash columns.
// clang-format off
#define STRATA_SHARED_BEGIN namespace strata::shared {
#define STRATA_SHARED_END }
#define STRATA_SHARED_FUNCTION inline
#define STRATA_SHARED_CLASS_BEGIN(name) class name { public: virtual ~name() = default;
#define STRATA_SHARED_FETCH(signature) virtual signature = 0;
#define STRATA_SHARED_CLASS_END };
#else
#define STRATA_SHARED_BEGIN
#define STRATA_SHARED_END
#define STRATA_SHARED_FUNCTION
#define STRATA_SHARED_CLASS_BEGIN(name)
#define STRATA_SHARED_FETCH(signature) signature;
#define STRATA_SHARED_CLASS_END
// clang-format on
#endif
