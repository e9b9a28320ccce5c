#version 450 core
// Fragment stage of every surface program: relief mapping (Policarpo, Oliveira, Comba 2005, Sec. 3 and the
// appendix's main_frag_relief), parallax, normal and texture mapping, plain surfaces, and the debug outputs
// of CONVENTIONS §7. docs/renderer.md describes the variants.
//
// Variant flags (src/gl/relief_program.cpp, variantDefines), one of each group:
//   STRATA_PLAIN | STRATA_TECHNIQUE_TEXTURE | STRATA_TECHNIQUE_NORMAL | STRATA_TECHNIQUE_PARALLAX |
//   STRATA_TECHNIQUE_RELIEF | STRATA_TECHNIQUE_MAXMIP | STRATA_TECHNIQUE_CONE | STRATA_TECHNIQUE_DUAL_DEPTH
//   STRATA_OUTPUT_SHADED | STRATA_OUTPUT_UV | STRATA_OUTPUT_SHADOW | STRATA_OUTPUT_DEPTH
// and optionally STRATA_SHADOWS (the shaded and shadow outputs of every technique), STRATA_DEPTH_CORRECTION
// (relief, parallax), STRATA_AO (ambient times the packed texture's AO) with STRATA_AO_PAPER (rescaled
// with aoRescalePaper), STRATA_META_LIVE (a live meta-relief's layers, relief_search.glsl, metaShade).
//
// Spaces. "Tile space" is the tangent frame (T, B, N) measured in tile units: x along T, y along B, z out
// of the surface; the relief lies at z = -S d. One tile unit is tileLength.x / .y / .z world units along
// T / B / N (relief.vert.glsl), so a world vector w has tile-space coordinates
// (w.T / tileLength.x, w.B / tileLength.y, w.N / tileLength.z).

#include "relief_search.glsl"
// Before the technique files that use it: includes are pasted once, whatever #ifdef is around them, so
// one pasted inside a disabled #ifdef would be missing from the others.
#include "bilinear_cell.glsl"
#ifdef STRATA_TECHNIQUE_MAXMIP
#include "maxmip.glsl"
#endif
#ifdef STRATA_TECHNIQUE_CONE
#include "cone.glsl"
#endif
#ifdef STRATA_TECHNIQUE_DUAL_DEPTH
#include "dual_depth.glsl"
#endif
#include "shared/ao_rescale.h"

in VertexData {
    vec3 worldPosition;
    vec3 normal;
    vec3 tangent;
    vec3 bitangent;
    vec2 tile;
    vec3 tileLength;
} vIn;

// The per-draw uniforms (uEye, uDepthScale, the light, ...): shared/relief_uniforms.h (relief_search.glsl).
layout(binding = kColorUnit) uniform sampler2D uColor;  // SRGB8_ALPHA8: sampling returns linear colour
// The packed relief texture again, with its own 16x anisotropic filtering, for the shaded output's final
// normal and AO fetch (the searches read uRelief through a trilinear sampler: relief_renderer.cpp).
layout(binding = kReliefShadeUnit) uniform sampler2D uReliefShade;

#ifdef STRATA_DEPTH_CORRECTION
// The relief point is never nearer than the polygon (t >= 0 along the view ray), so depth only grows: the
// driver may keep its early depth rejection against the polygon's depth.
layout(depth_greater) out float gl_FragDepth;
#endif

layout(location = 0) out vec4 fColor;

// The sRGB transfer function (IEC 61966-2-1), for uEncodeSrgb.
vec3 linearToSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// The packed normal (CONVENTIONS §5: R, G = n.xy * 0.5 + 0.5, nz = sqrt(1 - nx^2 - ny^2)) at the render's
// depth scale. A depth-derived normal is normalize(S dd/du, S dd/dv, 1) (CONVENTIONS §3), so scaling
// (nx, ny) by S_render / S_material and renormalising is exact for it (for a normal map that did not come
// from the depth it is the same linear stretch of the relief).
vec3 tileNormal(vec4 texel) {
    vec2 xy = texel.rg * 2.0 - 1.0;
    float z = sqrt(max(1.0 - dot(xy, xy), 0.0));
    return normalize(vec3(xy * uNormalScale, z));
}

#ifdef STRATA_META_LIVE
// uLayerNormalWeight, uLayerAoScale, uMetaConsistent, uLayerNormalScale, uMetaAo: the per-draw block.
layout(binding = kComposedAoUnit) uniform sampler2D uComposedAo;  // R: AO of the composed depth (uMetaAo 3)

// The shaded normal (tile space, at the render's S) and AO of a live meta-relief at tile coordinates uv.
//   paper (Eq. 1): n = normalize(sum_i w_n,i n_i(t_i uv)), then rescaled to the render's S like a baked
//     map (tileNormal), the layers' normal maps being valid at the material's S;
//   consistent: the layers hold normalize(S_L g_i, 1), g_i = grad d_i (CONVENTIONS §3, S_L =
//     uLayerNormalScale[i], small enough that the normals are nearly linear in g: uploadLiveMaterial), so
//     g_i = n.xy / (n.z S_L); the composed depth's gradient is, by the chain rule,
//     G = sum_i (w_d,i / W) t_i g_i(t_i uv), and n = normalize(S G, 1) at the render's S exactly.
// AO: each layer's B channel is its AO baked at S_i = S (w_d,i / W) t_i; rescaled per fragment to the
// current weights by Eq. 4-6 and combined by product or minimum, as the paper does; or the composed AO map.
void metaShade(vec2 uv, out vec3 n, out float ao) {
    vec3 sum = vec3(0.0);
    vec2 gradient = vec2(0.0);
    float aoProduct = 1.0;
    float aoMin = 1.0;
    for (int i = 0; i < kMaxLiveLayers; ++i) {
        if (i >= uLayerCount) break;
        float t = uLayerTiling[i];
        vec2 layerUv = uv * t;
        vec4 texel = textureGrad(uLayers[i], layerUv - floor(layerUv), gTileDx * t, gTileDy * t);
        vec2 xy = texel.rg * 2.0 - 1.0;
        vec3 ni = vec3(xy, sqrt(max(1.0 - dot(xy, xy), 0.0)));
        sum += uLayerNormalWeight[i] * ni;
        gradient += uLayerDepthWeight[i] * t * ni.xy / (max(ni.z, 1e-4) * uLayerNormalScale[i]);
        if (uLayerDepthWeight[i] > 0.0) {
            float layerAo = aoRescalePaper(texel.b, uLayerAoScale[i]);
            aoProduct *= layerAo;
            aoMin = min(aoMin, layerAo);
        }
    }
    if (uMetaConsistent != 0) {
        n = normalize(vec3(uDepthScale * gradient, 1.0));
    } else {
        vec3 m = normalize(sum);
        n = normalize(vec3(m.xy * uNormalScale, m.z));
    }
    ao = 1.0;
#ifdef STRATA_AO
    if (uMetaAo == 1) ao = aoProduct;
    if (uMetaAo == 2) ao = aoMin;
    if (uMetaAo == 3) {
        vec2 wrapped = uv - floor(uv);
        ao = textureGrad(uComposedAo, wrapped, gTileDx, gTileDy).r;
#ifdef STRATA_AO_PAPER
        ao = aoRescalePaper(ao, uAoScale);
#endif
    }
#endif
}
#endif

void main() {
    vec3 N = normalize(vIn.normal);
    vec3 T = normalize(vIn.tangent);
    vec3 B = normalize(vIn.bitangent);
    vec3 tileLength = vIn.tileLength;
    vec2 tile = vIn.tile;
    // Derivatives in uniform control flow, for textureGrad inside the searches (relief_search.glsl).
    gTileDx = dFdx(tile);
    gTileDy = dFdy(tile);
#ifdef STRATA_META_LIVE
    layerLods();
#endif

    // Paper appendix: v = normalize(p), the view vector, and s, the view vector in tangent space with z
    // pointing into the surface (s.z = dot(N, -v)); here in tile units (see "Spaces").
    vec3 view = normalize(vIn.worldPosition - uEye);
    vec3 s = vec3(dot(view, T) / tileLength.x, dot(view, B) / tileLength.y, -dot(view, N) / tileLength.z);
    // A fragment whose view ray does not go into the surface (an interpolated normal facing away near a
    // silhouette) has no relief point; it is shaded at the polygon.
    bool entering = s.z > 0.0;

    vec2 hitUv = tile;     // tile coordinates of the visible point (not wrapped)
    float hitDepth = 0.0;  // its depth d
    float bracket = 0.0;   // the relief search's final window: the surface is within this above hitDepth
    bool hit = true;       // whether the fragment shows a point of the relief

#if defined(STRATA_TECHNIQUE_RELIEF)
    // Paper appendix: ds = s.xy * depth / s.z, the (u, v) travel from depth 0 to depth 1, and
    // d = ray_intersect_rm(rmtex, dp, ds); the step count adapts to the view angle (Sec. 3).
    if (entering) {
        vec2 ds = s.xy * uDepthScale / s.z;
        // Clamped: int() of a NaN (a degenerate frame) is undefined and must not become a huge loop bound.
        int steps = clamp(reliefLinearSteps(uLinearSteps, dot(view, N)), 1, 4 * uLinearSteps);
        hitDepth = reliefIntersect(tile, ds, steps, uBinarySteps);
        bracket = 1.0 / (float(steps) * exp2(float(max(uBinarySteps - 1, 0))));
        hitUv = tile + ds * hitDepth;
    } else {
        hit = false;
    }
#elif defined(STRATA_TECHNIQUE_MAXMIP)
    // Exact intersection (maxmip.glsl): no steps, no search window.
    if (entering) {
        hitDepth = maxMipIntersect(tile, s.xy * uDepthScale / s.z);
        hitUv = tile + s.xy * uDepthScale / s.z * hitDepth;
    } else {
        hit = false;
    }
#elif defined(STRATA_TECHNIQUE_CONE)
    // Exact intersection (cone.glsl): no steps, no search window.
    if (entering) {
        hitDepth = coneIntersect(tile, s.xy * uDepthScale / s.z);
        hitUv = tile + s.xy * uDepthScale / s.z * hitDepth;
    } else {
        hit = false;
    }
#elif defined(STRATA_TECHNIQUE_DUAL_DEPTH)
    // An impostor (dual_depth.glsl): rays that pass the object show what is behind the quad.
    if (entering) {
        vec2 ds = s.xy * uDepthScale / s.z;
        int steps = clamp(reliefLinearSteps(uLinearSteps, dot(view, N)), 1, 4 * uLinearSteps);
        hitDepth = dualDepthIntersect(tile, ds, steps, uBinarySteps, bracket);
        hit = hitDepth >= 0.0;
        hitDepth = max(hitDepth, 0.0);
        hitUv = tile + ds * hitDepth;
    } else {
        hit = false;
    }
#ifdef STRATA_OUTPUT_SHADED
    if (!hit) discard;
#endif
#elif defined(STRATA_TECHNIQUE_PARALLAX)
    // Parallax mapping (Kaneko et al. 2001, the paper's Sec. 2): read d at the fragment's own uv and move
    // along the view ray to that depth, uv' = uv + (d S) s.xy / s.z; with V = (-s.x, -s.y, s.z) the vector
    // towards the eye this is the usual offset -(d S) V.xy / V.z. One fetch, no search: right only where d
    // varies slowly.
    if (entering) {
        hitDepth = reliefDepth(tile);
        hitUv = tile + s.xy * (hitDepth * uDepthScale / s.z);
    } else {
        hit = false;
    }
#elif defined(STRATA_PLAIN)
    hit = false;  // no relief: the debug outputs show nothing
#endif

    // The visible point in world space: the fragment moved along the view ray to depth hitDepth (the tile
    // offset (hitUv - tile, -S hitDepth) is parallel to s, so this stays on the ray). Appendix: p += v*d*s.z.
    vec2 offset = hitUv - tile;
    vec3 hitWorld = vIn.worldPosition + T * (offset.x * tileLength.x) + B * (offset.y * tileLength.y) -
                    N * (hitDepth * uDepthScale * tileLength.z);

#ifdef STRATA_DEPTH_CORRECTION
    // Paper Sec. 5 and appendix, RM_DEPTHCORRECT: the depth of the relief point, not of the polygon, so that
    // other geometry interpenetrates the relief correctly.
    vec4 clip = uViewProjection * vec4(hitWorld, 1.0);
    gl_FragDepth = (gl_DepthRange.diff * (clip.z / clip.w) + gl_DepthRange.near + gl_DepthRange.far) * 0.5;
#endif

    // The light, in world space, from the visible point (a point light).
    vec3 toLightWorld = uLightPosition - hitWorld;
    // A light at or below the tangent plane shadows (every technique).
    bool lit = dot(toLightWorld, N) > 0.0;
#ifdef STRATA_SHADOWS
    // Sec. 3.1 and appendix RM_SHADOWS: the light ray through a point of the relief, searched from the top
    // down to it. Relief mapping (and maxmip, cone, dual-depth) tests its hit. Parallax, normal and texture mapping
    // find no point on the relief, so they test the relief point under the coordinates they shade,
    // (uv, d(uv)): the offset uv for parallax, the fragment's own for the other two. That point lies on the
    // surface (no search window).
    vec2 shadowUv = hitUv;
    float shadowDepth = hitDepth;
    float shadowBracket = bracket;
    vec3 shadowWorld = hitWorld;
#if defined(STRATA_TECHNIQUE_TEXTURE) || defined(STRATA_TECHNIQUE_NORMAL) || defined(STRATA_TECHNIQUE_PARALLAX)
    shadowDepth = reliefDepth(hitUv);
    shadowBracket = 0.0;
    shadowWorld -= N * ((shadowDepth - hitDepth) * uDepthScale * tileLength.z);
#endif
    if (lit && hit) {
        vec3 toLight = uLightPosition - shadowWorld;
        vec3 toLightTile = vec3(dot(toLight, T) / tileLength.x, dot(toLight, B) / tileLength.y,
                                dot(toLight, N) / tileLength.z);
#if defined(STRATA_TECHNIQUE_DUAL_DEPTH)
        float cosLight = dot(normalize(toLight), N);
        int lightSteps = clamp(reliefLinearSteps(uLinearSteps, cosLight), 1, 4 * uLinearSteps);
        lit = dualLit(shadowUv, shadowDepth, shadowBracket, toLightTile, uDepthScale, lightSteps);
#elif defined(STRATA_TECHNIQUE_MAXMIP) || defined(STRATA_TECHNIQUE_CONE)
        // Exact: the light ray's first intersection from the top, by the same traversal; lit when that is
        // the point itself (within the bias of relief_search.glsl).
        if (toLightTile.z > 0.0) {
            vec2 up = toLightTile.xy * uDepthScale / toLightTile.z;
#ifdef STRATA_TECHNIQUE_CONE
            float first = coneIntersect(shadowUv + up * shadowDepth, -up);
#else
            float first = maxMipIntersect(shadowUv + up * shadowDepth, -up);
#endif
            lit = first >= shadowDepth - kShadowBias;
        } else {
            lit = false;
        }
#else
        float cosLight = dot(normalize(toLight), N);
        int lightSteps = clamp(reliefLinearSteps(uLinearSteps, cosLight), 1, 4 * uLinearSteps);
        lit = reliefLit(shadowUv, shadowDepth, shadowBracket, toLightTile, uDepthScale, lightSteps);
#endif
    }
#endif

#if defined(STRATA_OUTPUT_UV)
    // CONVENTIONS §7: (u, v) of the first hit modulo 1, and 1 for a hit. fract() of a value just below an
    // integer rounds to 1.0 in float; that is u = 0 of the next tile.
    vec2 uv = fract(hitUv);
    uv = mix(uv, vec2(0.0), greaterThanEqual(uv, vec2(1.0)));
    fColor = hit ? vec4(uv, 1.0, 1.0) : vec4(0.0, 0.0, 0.0, 1.0);
#elif defined(STRATA_OUTPUT_DEPTH)
    fColor = vec4(hit ? hitDepth : 0.0, 0.0, 0.0, 1.0);
#elif defined(STRATA_OUTPUT_SHADOW)
    fColor = vec4(hit && lit ? 1.0 : 0.0, 0.0, 0.0, 1.0);
#else
    // Shaded: Blinn-Phong with one point light (paper appendix: ambient * colour + diffuse + specular), in
    // linear RGB. Albedo and normal come from the visible point's tile coordinates, sampled with the
    // fragment's derivatives (mip mapping and anisotropic filtering, paper Sec. 5).
    vec3 albedo;
    vec3 normal = N;
    float ao = 1.0;
#ifdef STRATA_PLAIN
    albedo = uPlainColor;
#else
    // The fetches take the hit's coordinates modulo 1 (the textures repeat; the footprint comes from the
    // explicit derivatives, so nothing else changes). Near silhouettes s.z -> 0 and the searches' offsets
    // reach thousands of tiles; llvmpipe's anisotropic filter stalls for seconds per fragment at such
    // coordinates (a 1280x720 teapot took minutes instead of 2 s; docs/renderer.md).
    // The colour map repeats uColorTiling times per tile (a live meta-relief's colour layer; 1 otherwise).
    vec2 colorUv = hitUv * uColorTiling;
    albedo = textureGrad(uColor, colorUv - floor(colorUv), gTileDx * uColorTiling, gTileDy * uColorTiling).rgb;
#if !defined(STRATA_TECHNIQUE_TEXTURE)
#ifdef STRATA_META_LIVE
    vec3 n;
    metaShade(hitUv, n, ao);
#else
    vec2 shadeUv = hitUv - floor(hitUv);
    vec4 texel = textureGrad(uReliefShade, shadeUv, gTileDx, gTileDy);
    vec3 n = tileNormal(texel);
#ifdef STRATA_AO
    // Texture-space AO (Limberger et al. 2015, Sec. IV), in the packed texture's B channel; with
    // STRATA_AO_PAPER rescaled to the render's depth scale by Eq. 4-6 (shaders/shared/ao_rescale.h).
    ao = texel.b;
#ifdef STRATA_AO_PAPER
    ao = aoRescalePaper(ao, uAoScale);
#endif
#endif
#endif
    // Tile-space normal to world: normals transform with the inverse of the tile -> world scaling.
    normal = normalize(T * (n.x / tileLength.x) + B * (n.y / tileLength.y) + N * (n.z / tileLength.z));
#endif
#endif
    vec3 L = normalize(toLightWorld);
    vec3 V = normalize(uEye - hitWorld);
    vec3 H = normalize(L + V);
    float diffuse = max(dot(normal, L), 0.0);
    float specular = diffuse > 0.0 ? uSpecular * pow(max(dot(normal, H), 0.0), uShininess) : 0.0;
    vec3 color = uAmbient * ao * albedo;
    if (lit) color += uLightColor * (diffuse * albedo + specular);
    fColor = vec4(uEncodeSrgb != 0 ? linearToSrgb(color) : color, 1.0);
#endif
}
