// Cameras on the wire: SceneSpec.cameras to the engine's CameraConfig and back, rendered images
// to Observation.cameras (raw bytes or PNG/JPEG plus the ManiSkill camera matrices), and the
// image arrays of the CreateSession spec handshake.
#pragma once

#include "culinarycut/v1/simulator.pb.h"
#include "sim/render/camera_renderer.h"
#include "sim/world/model.h"

namespace culinarycut::server {

// Throws FieldError for a malformed pose, a non-finite value or a size past any int; the rest is
// checked when the model compiles.
CameraConfig CameraFromWire(const v1::CameraSpec& wire, const std::string& field);
void CameraToWire(const CameraConfig& camera, v1::CameraSpec* wire);

// One CameraImage per model camera (in order) and the segmentation labels, encoded as the scene asked.
// Throws render::RenderError when PNG/JPEG encoding fails.
void CameraImagesToWire(const Model& model, const render::RenderResult& images, v1::Observation* wire);

// sensor_data/<camera>/{rgb, depth, segmentation} and sensor_param/<camera>/{intrinsic_cv, extrinsic_cv,
// cam2world_gl} array specs.
void DescribeCameraSpaces(const Model& model, v1::CreateSessionResponse* response);

}  // namespace culinarycut::server
