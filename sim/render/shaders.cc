#include "sim/render/shaders.h"

#include <string>

namespace culinarycut::render {

const char* const kShadowVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_model;
uniform mat4 u_light_view_projection;
void main() { gl_Position = u_light_view_projection * u_model * vec4(a_position, 1.0); }
)";

const char* const kShadowFragmentShader = R"(#version 330 core
void main() {}
)";

const char* const kSceneVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_flesh;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view;
uniform mat4 u_projection;
uniform mat4 u_light_view_projection;
out vec3 v_world;
out vec3 v_normal;
out float v_flesh;
out vec4 v_light_clip;
out float v_eye_depth;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  vec4 eye = u_view * world;
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_flesh = a_flesh;
  v_light_clip = u_light_view_projection * world;
  v_eye_depth = -eye.z;  // OpenGL eye looks down -z: distance along the optical axis (m)
  gl_Position = u_projection * eye;
}
)";

// Compiled once per material: MATERIAL (MaterialKind in material.h) is defined by
// SceneFragmentShader. llvmpipe runs both sides of a branch under a mask, so one program with a
// runtime switch would pay for every material's noise on every pixel.
const char* const kSceneFragmentShaderBody = R"(
in vec3 v_world;
in vec3 v_normal;
in float v_flesh;
in vec4 v_light_clip;
in float v_eye_depth;
uniform vec3 u_color;
uniform vec3 u_second_color;
uniform float u_specular;
uniform float u_shininess;
uniform float u_pattern_scale;
uniform int u_segment;
uniform vec3 u_direction_to_light;
uniform vec3 u_light_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform vec3 u_camera_position;
uniform sampler2DShadow u_shadow_map;
uniform int u_shadows;
layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_depth;
layout(location = 2) out int out_segment;

float Hash(vec2 p) { return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453); }
float Noise(vec2 p) {
  vec2 i = floor(p);
  vec2 f = fract(p);
  vec2 u = f * f * (3.0 - 2.0 * f);
  return mix(mix(Hash(i), Hash(i + vec2(1.0, 0.0)), u.x), mix(Hash(i + vec2(0.0, 1.0)), Hash(i + vec2(1.0, 1.0)), u.x), u.y);
}
// Two world coordinates across the surface: the axes the normal is least aligned with.
vec2 PlaneCoords(vec3 p, vec3 n) {
  vec3 a = abs(n);
  if (a.z >= a.x && a.z >= a.y) return p.xy;
  if (a.x >= a.y) return p.yz;
  return p.xz;
}
float Shadow() {
  if (u_shadows == 0) return 1.0;
  vec3 c = v_light_clip.xyz / v_light_clip.w * 0.5 + 0.5;
  if (c.x < 0.0 || c.x > 1.0 || c.y < 0.0 || c.y > 1.0 || c.z > 1.0) return 1.0;
  // One bilinear-compared tap (2 x 2 texel PCF in the sampler): soft enough, and shadow lookups
  // are a large part of llvmpipe's per-pixel cost.
  return texture(u_shadow_map, c);
}

void main() {
  out_depth = v_eye_depth;
  out_segment = u_segment;
#if MATERIAL == 7  // emissive
  out_color = vec4(pow(min(u_color, vec3(1.0)), vec3(1.0 / 2.2)), 1.0);
  return;
#endif
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 view = normalize(u_camera_position - v_world);
  vec3 albedo = u_color;
  float specular = u_specular;
  float shininess = u_shininess;
  vec2 uv = PlaneCoords(v_world, n);
#if MATERIAL == 1  // wood: rings across y, stretched along x, with knots of noise
    float warp = Noise(vec2(v_world.x * 4.0, v_world.y * 25.0)) * 1.2;
    float ring = fract(v_world.y / u_pattern_scale + warp);
    float late = smoothstep(0.75, 0.95, ring);  // thin dark late-wood lines
    albedo = mix(u_color, u_second_color, 0.6 * late + 0.25 * Noise(vec2(v_world.x * 8.0, v_world.y * 90.0)));
#elif MATERIAL == 2  // tiles with grout and a per-tile tint
    vec2 cell = uv / u_pattern_scale;
    vec2 f = fract(cell);
    float edge = min(min(f.x, 1.0 - f.x), min(f.y, 1.0 - f.y)) * u_pattern_scale;
    float tint = 0.93 + 0.07 * Hash(floor(cell));
    albedo = edge < 0.0025 ? u_second_color : u_color * tint;
    if (edge < 0.0025) specular = 0.02;
#elif MATERIAL == 3  // brushed metal
    albedo = u_color * (0.92 + 0.08 * Noise(vec2(v_world.x * 800.0, v_world.y * 8.0)));
#elif MATERIAL == 4  // food: skin to flesh
    float flesh = clamp(v_flesh, 0.0, 1.0);
    float mottle = 0.85 + 0.15 * Noise(v_world.xy * 120.0);
    albedo = mix(u_color * mottle, u_second_color, flesh);
    specular = mix(u_specular, 0.35, flesh);  // cut flesh is wet
#elif MATERIAL == 5  // speckled stone
    float fleck = smoothstep(0.8, 0.95, Noise(uv / u_pattern_scale));
    albedo = mix(u_color * (0.92 + 0.08 * Noise(uv * 12.0)), u_second_color, fleck * 0.5);
#elif MATERIAL == 6  // planks along x
    float row = floor(uv.y / u_pattern_scale);
    float along = uv.x + Hash(vec2(row, 3.0)) * 2.0;
    float seam_y = fract(uv.y / u_pattern_scale);
    float seam_x = fract(along / 1.2);
    float seam = (seam_y < 0.02 || seam_x < 0.004) ? 1.0 : 0.0;
    float grain = Noise(vec2(along * 4.0, uv.y * 120.0));
    albedo = mix(u_color * (0.85 + 0.3 * Hash(vec2(row, 7.0)) * 0.5 + 0.15 * grain), u_second_color, seam);
#endif
  float lambert = max(dot(n, u_direction_to_light), 0.0);
  float shadow = lambert > 0.0 ? Shadow() : 0.0;
  vec3 halfway = normalize(u_direction_to_light + view);
  float highlight = pow(max(dot(n, halfway), 0.0), shininess) * specular * shadow * step(0.0, lambert);
  vec3 ambient = mix(u_ground_color, u_sky_color, 0.5 + 0.5 * n.z);
  vec3 color = albedo * (ambient + u_light_color * lambert * shadow) + u_light_color * highlight;
#if MATERIAL == 3  // steel mirrors the room: bright above, dark below
  vec3 r = reflect(-view, n);
  color += u_color * mix(u_ground_color, u_sky_color * 2.0, 0.5 + 0.5 * r.z) * 0.5;
#endif
  out_color = vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";

std::string SceneFragmentShader(int material_kind) {
  return "#version 330 core\n#define MATERIAL " + std::to_string(material_kind) + "\n" + kSceneFragmentShaderBody;
}

}  // namespace culinarycut::render
