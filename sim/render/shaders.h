// GLSL 3.30 core sources: the shadow-map pass and the camera pass (Blinn-Phong, one shadowed
// directional light, hemisphere ambient, procedural materials, gamma), which also writes metric
// eye depth and the segment id to their own attachments.
#pragma once

#include <string>

namespace culinarycut::render {

extern const char* const kShadowVertexShader;
extern const char* const kShadowFragmentShader;
extern const char* const kSceneVertexShader;
// The camera pass's fragment shader specialised for one MaterialKind (as int).
std::string SceneFragmentShader(int material_kind);

}  // namespace culinarycut::render
