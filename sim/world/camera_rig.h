// The cameras a scene declares, resolved into the renderer's camera specs when the model compiles:
// default poses for the named default cameras, sizes and channels checked. A scene without
// cameras gets none and never starts a renderer.
#pragma once

#include <vector>

#include "sim/render/camera.h"
#include "sim/robot/robot_description.h"
#include "sim/world/scene_config.h"
#include "sim/core/scene_layout.h"

namespace culinarycut {

inline constexpr int kMaxCameras = 8;
inline constexpr int kMaxImageSide = 2048;  // pixels; keeps one observation within a few 10 MB
inline constexpr int kDefaultImageSide = 224;  // the policies' input size (paper)

// Throws SceneError naming the field at fault: a duplicate or empty name, an unknown channel or
// encoding, a size outside [16, 2048], a camera without a pose that is not a default camera
// (front, left, right, wrist), or a link the robot does not have.
std::vector<render::CameraSpec> ResolveCameras(const std::vector<CameraConfig>& cameras, const SceneLayout& layout,
                                               const RobotDescription& robot);

}  // namespace culinarycut
