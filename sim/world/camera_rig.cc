#include "sim/world/camera_rig.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <string>

#include "sim/world/model.h"

namespace culinarycut {
namespace {

// The default camera of that name at this size, if there is one.
std::optional<render::CameraSpec> DefaultCamera(const std::string& name, const SceneLayout& layout, int width,
                                                int height) {
  if (name == "wrist") return render::WristCamera(width, height);
  for (const render::CameraSpec& camera : render::DefaultCameras(layout, width, height)) {
    if (camera.name == name) return camera;
  }
  return std::nullopt;
}

// Camera names become keys (sensor_data/<name>/rgb): letters, digits, '_' and '-' only.
bool IsValidName(const std::string& name) {
  return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-';
  });
}

bool RobotHasLink(const RobotDescription& robot, const std::string& link) {
  if (robot.base.name == link || robot.tip_frames.count(link) != 0) return true;
  return std::any_of(robot.links.begin(), robot.links.end(), [&](const RigidLink& l) { return l.name == link; });
}

int ImageSide(int requested, const std::string& field) {
  const int side = requested == 0 ? kDefaultImageSide : requested;
  if (side < 16 || side > kMaxImageSide) {
    throw SceneError(field + " must be in [16, " + std::to_string(kMaxImageSide) + "] pixels (0 means " +
                     std::to_string(kDefaultImageSide) + "), got " + std::to_string(requested));
  }
  return side;
}

}  // namespace

std::vector<render::CameraSpec> ResolveCameras(const std::vector<CameraConfig>& cameras, const SceneLayout& layout,
                                               const RobotDescription& robot) {
  if (cameras.size() > static_cast<std::size_t>(kMaxCameras)) {
    throw SceneError("scene.cameras has " + std::to_string(cameras.size()) + " cameras; at most " +
                     std::to_string(kMaxCameras) + " are allowed");
  }
  std::vector<render::CameraSpec> resolved;
  std::set<std::string> names;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const CameraConfig& config = cameras[i];
    const std::string field = "scene.cameras[" + std::to_string(i) + "]";
    if (!IsValidName(config.name)) {
      throw SceneError(field + ".name must be 1-64 letters, digits, '_' or '-' (e.g. \"front\"), got \"" +
                       config.name + "\"");
    }
    if (!names.insert(config.name).second) throw SceneError(field + ".name \"" + config.name + "\" is used twice");
    const int width = ImageSide(config.width, field + ".width");
    const int height = ImageSide(config.height, field + ".height");

    render::CameraSpec camera;
    if (config.pose) {
      camera.pose_in_world = *config.pose;
      camera.attached_link = config.attached_link;
    } else if (std::optional<render::CameraSpec> preset = DefaultCamera(config.name, layout, width, height)) {
      if (!config.attached_link.empty()) {
        throw SceneError(field + ".attached_link needs a pose in that link's frame; give pose or leave attached_link empty");
      }
      camera = *preset;
    } else {
      throw SceneError(field + " (\"" + config.name +
                       "\") needs a pose; only the default cameras front, left, right and wrist have one");
    }
    if (!camera.attached_link.empty() && !RobotHasLink(robot, camera.attached_link)) {
      throw SceneError(field + ".attached_link \"" + camera.attached_link + "\" is not a link of the robot " +
                       robot.name + " (e.g. panda_link8 is the flange)");
    }
    camera.name = config.name;
    camera.width = width;
    camera.height = height;
    if (config.fov_y_deg != 0.0) camera.fov_y_deg = config.fov_y_deg;
    if (!(camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0)) {
      throw SceneError(field + ".fov_y_deg must be in (0, 180) degrees, got " + std::to_string(config.fov_y_deg));
    }

    camera.rgb = config.channels.empty();
    std::set<std::string> channels;
    for (const std::string& channel : config.channels) {
      if (!channels.insert(channel).second) throw SceneError(field + ".channels lists \"" + channel + "\" twice");
      if (channel == "rgb") {
        camera.rgb = true;
      } else if (channel == "depth") {
        camera.depth = true;
      } else if (channel == "segmentation") {
        camera.segmentation = true;
      } else {
        throw SceneError(field + ".channels: unknown channel \"" + channel + "\"; use rgb, depth or segmentation");
      }
    }
    const std::string& encoding = config.rgb_encoding;
    if (!encoding.empty() && encoding != "raw" && encoding != "png" && encoding != "jpeg") {
      throw SceneError(field + ".rgb_encoding must be raw, png or jpeg, got \"" + encoding + "\"");
    }
    if ((encoding == "png" || encoding == "jpeg") && !camera.rgb) {
      throw SceneError(field + ".rgb_encoding is " + encoding + " but the camera has no rgb channel");
    }
    resolved.push_back(camera);
  }
  return resolved;
}

}  // namespace culinarycut
