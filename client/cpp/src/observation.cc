#include "culinarycut/observation.h"

#include <algorithm>
#include <cstring>

namespace culinarycut::client {
namespace {

std::vector<double> ToVector(const google::protobuf::RepeatedField<double>& field) {
  return std::vector<double>(field.begin(), field.end());
}

template <std::size_t N>
std::array<double, N> ToArray(const google::protobuf::RepeatedField<double>& field) {
  std::array<double, N> out{};
  std::copy_n(field.begin(), std::min<std::size_t>(N, field.size()), out.begin());
  return out;
}

// The little-endian pixel bytes of a bytes field as an array of T.
template <typename T>
std::vector<T> Unpack(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

CameraImage CameraFromWire(const v1::CameraImage& wire) {
  CameraImage image;
  image.name = wire.name();
  image.width = static_cast<int>(wire.width());
  image.height = static_cast<int>(wire.height());
  image.rgb_encoding = wire.rgb_encoding().empty() ? "raw" : wire.rgb_encoding();
  if (image.rgb_encoding == "raw") {
    image.rgb.assign(wire.rgb().begin(), wire.rgb().end());
  } else {
    image.rgb_encoded = wire.rgb();
  }
  image.depth_m = Unpack<float>(wire.depth());
  image.segmentation = Unpack<std::int32_t>(wire.segmentation());
  image.intrinsic_cv = ToArray<9>(wire.intrinsic_cv());
  image.extrinsic_cv = ToArray<12>(wire.extrinsic_cv());
  image.cam2world_gl = ToArray<16>(wire.cam2world_gl());
  return image;
}

}  // namespace

Observation FromWire(const v1::FrameStamp& stamp, const v1::Observation& wire) {
  Observation observation;
  observation.frame_id = stamp.frame_id();
  observation.sim_time = stamp.sim_time();
  observation.qpos = ToVector(wire.agent().qpos());
  observation.qvel = ToVector(wire.agent().qvel());
  observation.qpos_target = ToVector(wire.agent().qpos_target());
  observation.tcp_pose = ToVector(wire.tcp_pose());
  observation.tcp_velocity = ToVector(wire.tcp_velocity());
  observation.flange_pose = ToVector(wire.flange_pose());
  observation.wrist_wrench = ToVector(wire.wrist_wrench());
  observation.instruction = wire.instruction();
  if (wire.has_food()) {
    FoodObservation food;
    food.knife_contact = wire.food().knife_contact();
    food.mpm_awake = wire.food().mpm_awake();
    for (const v1::FoodPiece& piece : wire.food().pieces()) {
      food.pieces.push_back(FoodPiece{piece.object(), piece.particles(), piece.volume(), ToArray<3>(piece.centroid()),
                                      ToArray<3>(piece.bounds_min()), ToArray<3>(piece.bounds_max())});
    }
    observation.food = std::move(food);
  }
  for (const v1::CameraImage& camera : wire.cameras()) observation.cameras.push_back(CameraFromWire(camera));
  observation.segmentation_labels.assign(wire.segmentation_labels().begin(), wire.segmentation_labels().end());
  return observation;
}

}  // namespace culinarycut::client
