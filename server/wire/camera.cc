#include "server/wire/camera.h"

#include <algorithm>

#include "server/wire/values.h"
#include "sim/render/image_encoding.h"

namespace culinarycut::server {
namespace {

// `low` / `high` with one value apply to every element; empty means unbounded.
void AddImageSpec(v1::CreateSessionResponse* response, const std::string& name, std::vector<std::uint32_t> shape,
                  const std::string& dtype, const std::string& description, std::vector<double> low = {},
                  std::vector<double> high = {}) {
  v1::ArraySpec* spec = response->add_observation_spec();
  spec->mutable_low()->Assign(low.begin(), low.end());
  spec->mutable_high()->Assign(high.begin(), high.end());
  spec->set_name(name);
  for (std::uint32_t side : shape) spec->add_shape(side);
  spec->set_dtype(dtype);
  spec->set_description(description);
}

}  // namespace

CameraConfig CameraFromWire(const v1::CameraSpec& wire, const std::string& field) {
  CameraConfig camera;
  camera.name = TextFromWire(wire.name(), field + ".name");
  const v1::Pose& pose = wire.pose();
  if (pose.position_size() != 0 || pose.quaternion_size() != 0) {  // neither: a default camera's pose
    camera.pose = PoseFromWire(pose, field + ".pose");
  }
  camera.attached_link = TextFromWire(wire.attached_link(), field + ".attached_link");
  camera.fov_y_deg = FiniteFromWire(wire.fov_y_deg(), field + ".fov_y_deg");
  // Sizes fit an int here; the model checks the supported range (scene_config.h).
  camera.width = CountFromWire(wire.width(), 1u << 20, field + ".width");
  camera.height = CountFromWire(wire.height(), 1u << 20, field + ".height");
  for (int i = 0; i < wire.channels_size(); ++i) {
    camera.channels.push_back(TextFromWire(wire.channels(i), field + ".channels[" + std::to_string(i) + "]"));
  }
  camera.rgb_encoding = TextFromWire(wire.rgb_encoding(), field + ".rgb_encoding");
  return camera;
}

void CameraToWire(const CameraConfig& camera, v1::CameraSpec* wire) {
  wire->set_name(camera.name);
  if (camera.pose) PoseToWire(*camera.pose, wire->mutable_pose());
  wire->set_attached_link(camera.attached_link);
  wire->set_fov_y_deg(camera.fov_y_deg);
  wire->set_width(static_cast<std::uint32_t>(camera.width));
  wire->set_height(static_cast<std::uint32_t>(camera.height));
  for (const std::string& channel : camera.channels) wire->add_channels(channel);
  wire->set_rgb_encoding(camera.rgb_encoding);
}

void CameraImagesToWire(const Model& model, const render::RenderResult& images, v1::Observation* wire) {
  for (std::size_t i = 0; i < images.cameras.size(); ++i) {
    const render::CameraImages& camera = images.cameras[i];
    const std::string& encoding = model.config.cameras.at(i).rgb_encoding;
    v1::CameraImage* out = wire->add_cameras();
    out->set_name(camera.name);
    out->set_width(static_cast<std::uint32_t>(camera.width));
    out->set_height(static_cast<std::uint32_t>(camera.height));
    if (!camera.rgb.empty()) {
      if (encoding == "png" || encoding == "jpeg") {
        AssignBytes(render::EncodeImage(camera, encoding), out->mutable_rgb());
      } else {
        AssignBytes(camera.rgb, out->mutable_rgb());
      }
      out->set_rgb_encoding(encoding);
    }
    AssignBytes(camera.depth_m, out->mutable_depth());
    AssignBytes(camera.segmentation, out->mutable_segmentation());
    AssignRowMajor(camera.intrinsics.K, 3, out->mutable_intrinsic_cv());
    AssignRowMajor(camera.extrinsics.world_to_camera.matrix(), 3, out->mutable_extrinsic_cv());
    // ManiSkill's cam2world_gl: the OpenGL camera frame (x right, y up, z back) in the world.
    const Eigen::Matrix4d cam2world_gl = camera.extrinsics.gl_view.inverse();
    AssignRowMajor(cam2world_gl, 4, out->mutable_cam2world_gl());
    AssignRowMajor(camera.intrinsics.gl_projection, 4, out->mutable_gl_projection());
  }
  const bool any_segmentation = std::any_of(model.cameras.begin(), model.cameras.end(),
                                            [](const render::CameraSpec& camera) { return camera.segmentation; });
  if (!any_segmentation) return;
  for (const render::SegmentLabel& label : images.labels) {
    v1::SegmentLabel* out = wire->add_segmentation_labels();
    out->set_id(label.id);
    out->set_kind(label.kind);
    out->set_object(label.object);
    out->set_piece(label.piece);
    out->set_food(label.food);
  }
}

void DescribeCameraSpaces(const Model& model, v1::CreateSessionResponse* response) {
  for (const render::CameraSpec& camera : model.cameras) {
    const std::string data = "sensor_data/" + camera.name + "/";
    const auto height = static_cast<std::uint32_t>(camera.height), width = static_cast<std::uint32_t>(camera.width);
    if (camera.rgb) AddImageSpec(response, data + "rgb", {height, width, 3}, "uint8", "colour image, row 0 at the top", {0}, {255});
    if (camera.depth) {
      AddImageSpec(response, data + "depth", {height, width, 1}, "float32",
                   "depth along the optical axis (m); 0 where nothing was hit", {0});
    }
    if (camera.segmentation) {
      AddImageSpec(response, data + "segmentation", {height, width, 1}, "int32",
                   "ids: 0 background, 1 robot, 2 knife, 3 board, 4.. food pieces (see the labels in info)", {0},
                   {2147483647.0});
    }
    const std::string param = "sensor_param/" + camera.name + "/";
    AddImageSpec(response, param + "intrinsic_cv", {3, 3}, "float32", "OpenCV K (pixels)");
    AddImageSpec(response, param + "extrinsic_cv", {3, 4}, "float32", "[R | t] world -> OpenCV camera frame");
    AddImageSpec(response, param + "cam2world_gl", {4, 4}, "float32", "OpenGL camera frame -> world");
  }
}

}  // namespace culinarycut::server
