// GLSL 330 core sources.  Feature switches are #defines inserted by glu::program: a scene that
// does not use a feature does not compile its code (DESIGN "scene.py").
#pragma once

namespace brushwork::shaders {

// Footprint pass (seed "Ink depositing"): the brush surface swept between the last deposit
// (u_t = 0) and this one (u_t = 1), seen orthographically from below; only the part under the
// paper (z < 0) leaves ink.  Attributes: last and current positions and ring centres (mm), uv =
// (along the spine, 0 root .. 1 tip; around the tuft, 0..1).
inline constexpr const char* kFootprintVertex = R"(#version 330 core
layout(location = 0) in vec3 a_prev;
layout(location = 1) in vec3 a_cur;
layout(location = 2) in vec3 a_center_prev;
layout(location = 3) in vec3 a_center_cur;
layout(location = 4) in vec2 a_uv;
// The whole sweep of one deposit is one instanced draw (a draw call costs more than its pixels
// on a software renderer): instance i < K blends the two surfaces at t = (i + 1) / K; the next
// Ks.x instances slide the last surface toward this one, the Ks.y after them slide this one back.
uniform int u_blends;   // K
uniform ivec2 u_slides; // Ks: copies of the last part, of this part (0: no slides)
uniform int u_first;    // instance number of this draw's first instance (one draw per kind)
uniform vec2 u_shift;   // mm, the move of the footprint's centre from the last deposit
uniform vec4 u_view;    // tile: (x0 mm, y0 mm, 2 / width mm, 2 / height mm)
uniform float u_soak;   // soak_expand * excess moisture
out vec2 v_uv;
out float v_z;
out vec2 v_mm;
#if defined(USE_SPLIT) || defined(USE_DRY)
// the stroke frame: paper mm along the path of the footprint's centre and across it, so that a
// point of the paper keeps its coordinates from one deposit to the next and streaks follow the
// stroke (the frame turns with the travel; its along coordinate goes on from deposit to deposit)
uniform vec4 u_frame;   // (centre x mm, centre y mm, unit travel direction x, y)
uniform float u_frame_s;  // mm the centre has travelled since the stroke began
out vec2 v_st;          // (along, across) mm
#endif
#if defined(USE_DRY) || defined(USE_GRAIN)
// wetness and pressure per spine node, interpolated here at the vertex's s: the rings include
// every node (s = i / n), so no triangle straddles one and the linear interpolation across the
// triangle is the piecewise-linear profile itself (and the fragment shader does no indexing)
uniform int u_nodes;          // spine nodes n + 1
uniform float u_wet[33];      // wetness per node, root first, [0, 1]
uniform float u_press[33];    // pressure per node, [0, 1]
out float v_wet;
out float v_press;
float along(float s, bool wet) {
  float x = clamp(s, 0.0, 1.0) * float(u_nodes - 1);
  int i = min(int(x), u_nodes - 2);
  return wet ? mix(u_wet[i], u_wet[i + 1], x - float(i)) : mix(u_press[i], u_press[i + 1], x - float(i));
}
#endif
void main() {
  int i = gl_InstanceID + u_first;
  float t;
  vec2 shift = vec2(0.0);
  if (i < u_blends) {
    t = float(i + 1) / float(u_blends);
  } else if (i < u_blends + u_slides.x) {
    t = 0.0;
    shift = u_shift * (float(i - u_blends + 1) / float(u_slides.x));
  } else {
    t = 1.0;
    shift = u_shift * (float(i - u_blends - u_slides.x + 1) / float(u_slides.y) - 1.0);
  }
  vec3 p = mix(a_prev, a_cur, t);
#ifdef USE_SOAK
  // seed "Soaked brush": the tip swells with excess moisture, more toward the tip
  vec3 c = mix(a_center_prev, a_center_cur, t);
  p = c + (p - c) * (1.0 + u_soak * smoothstep(0.5, 1.0, a_uv.x));
#endif
  p.xy += shift;
  v_uv = a_uv;
#if defined(USE_DRY) || defined(USE_GRAIN)
  v_wet = along(a_uv.x, true);
  v_press = along(a_uv.x, false);
#endif
  v_z = p.z;
  v_mm = p.xy;
#if defined(USE_SPLIT) || defined(USE_DRY)
  vec2 r = p.xy - u_frame.xy;
  v_st = vec2(u_frame_s + dot(r, u_frame.zw), dot(r, vec2(-u_frame.w, u_frame.z)));
#endif
  gl_Position = vec4((p.xy - u_view.xy) * u_view.zw - 1.0, 0.0, 1.0);
}
)";

inline constexpr const char* kFootprintFragment = R"(#version 330 core
in vec2 v_uv;
in float v_z;
in vec2 v_mm;
#if defined(USE_DRY) || defined(USE_GRAIN)
in float v_wet;               // wetness of the spine at this fragment's s, [0, 1]
in float v_press;             // pressure, [0, 1]
#endif
#if defined(USE_SPLIT) || defined(USE_DRY)
in vec2 v_st;                 // stroke frame (along, across), mm
#endif
uniform vec4 u_color;         // straight RGBA of the ink (no ramp)
uniform sampler2D u_split;    // an image for the split map: (across cells, along the spine) alpha
uniform sampler2D u_dry;      // an image of the dry map's lattice values (across, along)
uniform sampler2D u_grain;    // an image of the grain's lattice values (x, y)
uniform sampler2D u_ramp;     // (along, -) straight RGBA
uniform float u_soak_shift;   // soak_shift * excess moisture
uniform vec4 u_dry_param;     // dry onset, dry pressure, grain onset, grain pressure
uniform vec4 u_texture;       // 1 / streak width (1/mm), 1 / grain size (1/mm), dryness from speed,
                              // bits 1, 2: some node of this deposit is dry enough to open the dry
                              // field, the grain (a branch the whole draw takes alike)
uniform int u_seed;           // seed of the procedural fields
uniform int u_images;         // bits 1, 2, 4: the split, dry, grain fields come from images
#ifdef USE_DEPLETION
uniform float u_density;      // the ink's density for this tuft and deposit, [0, 1] (Paper::ink_density)
#endif
out vec4 o_color;

#if defined(USE_SPLIT) || defined(USE_DRY) || defined(USE_GRAIN)
// The maps are procedural fields on the paper, in mm (seed "Fine bristle effect", "Dry brush",
// "Grain texture"): value noise over an integer lattice whose values are a hash of the cell, so
// they never repeat and the output's resolution only samples them; an image given for a map
// replaces the hash by its texels (one per lattice cell, repeating)
float hash01(ivec2 c, int salt) {
  // pcg3d (Jarzynski and Olano 2020), 24 bits of the first component
  uvec3 v = uvec3(uint(c.x), uint(c.y), uint(salt) ^ (uint(u_seed) * 0x9E3779B9u));
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  return float(v.x >> 8u) * (1.0 / 16777216.0);
}
float lattice(ivec2 c, int salt, sampler2D image, bool own) {
  if (!own) return hash01(c, salt);
  ivec2 n = textureSize(image, 0);
  return texelFetch(image, c - n * ivec2(floor(vec2(c) / vec2(n))), 0).r;
}
// smooth value noise at x (lattice cells), in [0, 1]
float value_noise(vec2 x, int salt, sampler2D image, bool own) {
  vec2 i = floor(x), f = x - i, u = f * f * (3.0 - 2.0 * f);
  ivec2 c = ivec2(i);
  float a = lattice(c, salt, image, own), b = lattice(c + ivec2(1, 0), salt, image, own);
  float d = lattice(c + ivec2(0, 1), salt, image, own), e = lattice(c + ivec2(1, 1), salt, image, own);
  return mix(mix(a, b, u.x), mix(d, e, u.x), u.y);
}
// the two octaves' sum spread back over [0, 1] (value noise crowds the middle): thresholding
// at t then keeps about the fraction 1 - t
float spread(float n) {
  float x = clamp((n - 0.5) * 1.9, -1.0, 1.0);
  return 0.5 + 0.5 * x * (1.5 - 0.5 * x * x);
}
// the fraction of the pixel where the field f lies above the threshold t (the step filtered
// over the pixel's footprint: the same coverage at any resolution)
float above(float f, float t) {
  return clamp((f - t) / max(fwidth(f), 1e-4) + 0.5, 0.0, 1.0);
}
#endif

void main() {
  // coverage of the pixel by the part below the paper: the footprint's edge is where the
  // surface crosses z = 0; half a pixel of ramp on each side keeps it free of stair steps
  float a = clamp(0.5 - v_z / max(fwidth(v_z), 1e-7), 0.0, 1.0);
  if (a <= 0.0) discard;
  float s = v_uv.x;
#ifdef USE_RAMP
  // seed "Ink loading": the colour gradient mapped along the spine
  vec4 ink = texture(u_ramp, vec2(s, 0.5));
#else
  vec4 ink = u_color;
#endif
  vec3 rgb = ink.rgb;
  a *= ink.a;
#if defined(USE_SPLIT) || defined(USE_DRY)
  // the stroke frame in streak widths: across wanders slowly along the stroke, as hairs do
  const float kDryAlong = 1.0 / 50.0;  // streak widths along the stroke per lattice cell, over one
  vec2 st = v_st * u_texture.x;
  float across = st.y + 0.6 * value_noise(vec2(st.x * kDryAlong, 0.5), 7, u_split, false);
#endif
#ifdef USE_SPLIT
  // seed "Fine bristle effect": the tip parts into bristle groups.  The split map is a set of
  // gaps across the stroke, one lattice cell in four a gap that opens at its own point s0 along
  // the spine and widens toward the tip; only where the tip alone touches do they stay white
  // (any deposit of the belly over a point inks it).  Scaled toward the tip while soaked.
  float sp = s * (1.0 - u_soak_shift);
  if ((u_images & 1) != 0) {
    a *= texture(u_split, vec2(across / float(textureSize(u_split, 0).x), sp)).r;
  } else {
    ivec2 cell = ivec2(int(floor(across)), 0);
    float s0 = 0.45 + 0.45 * hash01(cell, 11);
    float half_tip = hash01(cell, 12) < 0.25 ? 0.1 + 0.3 * hash01(cell, 13) : 0.0;
    float half_w = half_tip * pow(clamp((sp - s0) / (1.0 - s0), 0.0, 1.0), 0.7);
    // the gap's coverage of the pixel: its edges filtered over the pixel, and a gap narrower
    // than the pixel in proportion to its width
    float fw = max(fwidth(across), 1e-4);
    float gap = clamp((half_w - abs(fract(across) - 0.5)) / fw + 0.5, 0.0, 1.0) * clamp(2.0 * half_w / fw, 0.0, 1.0);
    a *= 1.0 - gap;
  }
#endif
#if defined(USE_DRY) || defined(USE_GRAIN)
  float wet = v_wet;
  float press = v_press;
#endif
#ifdef USE_DRY
  // seed "Dry brush": only the peaks of the bristles' height field touch a dry brush; the
  // threshold rises as the node dries and as the brush moves faster, and falls with pressure.
  // The field: bristle clumps a streak wide across, long along the stroke
  // (the field and its coverage outside any per-fragment branch: fwidth needs the neighbouring
  // pixels')
  if ((int(u_texture.w) & 1) != 0) {
    float td = clamp(1.0 - wet / u_dry_param.x + u_texture.z - u_dry_param.y * press, 0.0, 1.0);
    bool own_dry = (u_images & 2) != 0;
    float hd = spread(0.65 * value_noise(vec2(st.x * kDryAlong, across), 3, u_dry, own_dry) +
                      0.35 * value_noise(vec2(st.x * (3.0 * kDryAlong), across * 2.3), 5, u_dry, own_dry));
    float cd = above(hd, td);
    if (td > 0.0) a *= cd;
  }
#endif
#ifdef USE_GRAIN
  // seed "Grain texture": the paper's valleys stay white under a rather dry brush
  if ((int(u_texture.w) & 2) != 0) {
    float tg = clamp(1.0 - wet / u_dry_param.z + u_texture.z - u_dry_param.w * press, 0.0, 1.0);
    bool own_grain = (u_images & 4) != 0;
    vec2 g = v_mm * u_texture.y;
    float hg = spread(0.6 * value_noise(g, 1, u_grain, own_grain) + 0.4 * value_noise(g * 2.7, 2, u_grain, own_grain));
    float cg = above(hg, tg);
    if (tg > 0.0) a *= cg;
  }
#endif
#ifdef USE_DEPLETION
  // an emptying brush gives less ink (the same density over the whole footprint, as the paper
  // draws it from the tuft's ink as one: what the brush spends is measured at that density)
  a *= u_density;
#endif
  if (a <= 1.0 / 4096.0) discard;
#ifdef USE_MAX_BLEND
  // the layer holds alpha alone (R32F); the stroke's colour is applied at the composite
  o_color = vec4(a, 0.0, 0.0, 0.0);
#else
  o_color = vec4(rgb * a, a);
#endif
#ifndef USE_MAX_BLEND
  // the stroke layer keeps the densest deposit per pixel (depth test LESS on 1 - alpha; with
  // one ink colour the blend equation MAX does it)
  gl_FragDepth = 1.0 - a;
#endif
}
)";

// Full-tile quad: composite the stroke layer over the paper (premultiplied "over", done by the
// blend unit with ONE, ONE_MINUS_SRC_ALPHA).
inline constexpr const char* kQuadVertex = R"(#version 330 core
layout(location = 0) in vec2 a_pos;
void main() { gl_Position = vec4(a_pos, 0.0, 1.0); }
)";

inline constexpr const char* kCompositeFragment = R"(#version 330 core
uniform sampler2D u_layer;
uniform vec4 u_layer_ink;   // (r, g, b, 1): the layer holds alpha alone; (0, 0, 0, 0): premultiplied RGBA
out vec4 o_color;
void main() {
  vec4 l = texelFetch(u_layer, ivec2(gl_FragCoord.xy), 0);
  o_color = u_layer_ink.a > 0.5 ? vec4(u_layer_ink.rgb * l.r, l.r) : l;
}
)";

}  // namespace brushwork::shaders

namespace brushwork::shaders {

// Brush view (seed "System prototype": the tuft shaded, or outlined for legibility, or
// transparent, with its shadow, over the painting, from an orthographic or perspective camera).
inline constexpr const char* kViewVertex = R"(#version 330 core
layout(location = 0) in vec3 a_pos;     // mm
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
uniform mat4 u_mvp;
uniform float u_push;       // mm along the normal (outline shell)
uniform vec3 u_flatten;     // shadow: project along this direction onto z = u_flatten_z
uniform float u_flatten_z;
uniform int u_shadow;
out vec3 v_normal;
out float v_s;
void main() {
  vec3 p = a_pos + a_normal * u_push;
  if (u_shadow == 1) p = vec3(p.xy - u_flatten.xy * (p.z / u_flatten.z), u_flatten_z);
  v_normal = a_normal;
  v_s = a_uv.x;
  gl_Position = u_mvp * vec4(p, 1.0);
}
)";

inline constexpr const char* kViewFragment = R"(#version 330 core
in vec3 v_normal;
in float v_s;
uniform sampler2D u_ramp;   // ink colour along the spine
uniform vec4 u_flat;        // a flat colour (outline, shadow), used when u_flat.a > 0
uniform int u_shade;        // 1: Lambert shading of the ink colour
uniform vec3 u_light;       // unit direction toward the light
uniform float u_alpha;
out vec4 o_color;
void main() {
  if (u_flat.a > 0.0) { o_color = u_flat; return; }
  vec3 ink = texture(u_ramp, vec2(v_s, 0.5)).rgb;
  // tufts loaded with black ink would read as a silhouette: lift the albedo a little
  vec3 albedo = mix(vec3(0.18), vec3(1.0), ink);
  vec3 c = albedo;
  if (u_shade == 1) {
    float d = max(dot(normalize(v_normal), u_light), 0.0);
    c = albedo * (0.35 + 0.65 * d) + vec3(0.08) * pow(d, 16.0);
  }
  o_color = vec4(c, u_alpha);
}
)";

inline constexpr const char* kPaperVertex = R"(#version 330 core
layout(location = 0) in vec2 a_mm;    // corner of a paper tile on z = 0
layout(location = 1) in vec2 a_uv;
uniform mat4 u_mvp;
out vec2 v_uv;
void main() { v_uv = a_uv; gl_Position = u_mvp * vec4(a_mm, 0.0, 1.0); }
)";

inline constexpr const char* kPaperFragment = R"(#version 330 core
in vec2 v_uv;
uniform sampler2D u_paper;   // premultiplied ink
uniform sampler2D u_layer;   // the stroke in progress, premultiplied
uniform int u_has_layer;
uniform vec4 u_layer_ink;   // as the composite's: (r, g, b, 1) alpha-only layer, 0 RGBA
uniform vec3 u_paper_color;
out vec4 o_color;
void main() {
  vec4 ink = texture(u_paper, v_uv);
  if (u_has_layer == 1) {
    vec4 l = texture(u_layer, v_uv);
    if (u_layer_ink.a > 0.5) l = vec4(u_layer_ink.rgb * l.r, l.r);
    ink = l + ink * (1.0 - l.a);
  }
  o_color = vec4(ink.rgb + u_paper_color * (1.0 - ink.a), 1.0);
}
)";

}  // namespace brushwork::shaders
