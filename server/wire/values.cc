#include "server/wire/values.h"

#include <cmath>
#include <sstream>

#include "sim/core/pose.h"

namespace culinarycut::server {

const std::string& TextFromWire(const std::string& value, const std::string& field, std::size_t max_length) {
  if (value.size() > max_length) {
    throw FieldError(field, "is " + std::to_string(value.size()) + " bytes long; at most " + std::to_string(max_length));
  }
  for (std::size_t i = 0; i < value.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(value[i]);
    if (c < 0x20 || c == 0x7f) {
      throw FieldError(field, "holds a control character (byte " + std::to_string(c) + " at position " +
                                  std::to_string(i) + "); use printable text");
    }
  }
  return value;
}

double FiniteFromWire(double value, const std::string& field) {
  if (!std::isfinite(value)) throw FieldError(field, "must be a finite number");
  return value;
}

double RangeFromWire(double value, double low, double high, const std::string& field, const std::string& unit) {
  if (!std::isfinite(value) || value < low || value > high) {
    std::ostringstream message;
    message << "must be in [" << low << ", " << high << "]" << (unit.empty() ? "" : " ") << unit;
    throw FieldError(field, message.str());
  }
  return value;
}

int CountFromWire(std::uint64_t value, std::uint64_t high, const std::string& field) {
  if (value > high) throw FieldError(field, "must be at most " + std::to_string(high));
  return static_cast<int>(value);
}

Eigen::Vector3d Vector3FromWire(const google::protobuf::RepeatedField<double>& values, const std::string& field) {
  if (values.size() != 3) throw FieldError(field, "must have 3 values, got " + std::to_string(values.size()));
  const Eigen::Vector3d vector(values[0], values[1], values[2]);
  if (!vector.allFinite()) throw FieldError(field, "has a non-finite value");
  return vector;
}

Eigen::Isometry3d PoseFromWire(const v1::Pose& wire, const std::string& field) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Vector3FromWire(wire.position(), field + ".position");
  if (wire.quaternion_size() != 4) {
    throw FieldError(field + ".quaternion",
                     "must have 4 values [w, x, y, z], got " + std::to_string(wire.quaternion_size()));
  }
  const std::optional<Eigen::Vector4d> wxyz = NormalizedQuaternion(
      {wire.quaternion(0), wire.quaternion(1), wire.quaternion(2), wire.quaternion(3)});
  if (!wxyz) throw FieldError(field + ".quaternion", "must be finite with a positive norm");
  pose.linear() = Eigen::Quaterniond((*wxyz)[0], (*wxyz)[1], (*wxyz)[2], (*wxyz)[3]).toRotationMatrix();
  return pose;
}

void PoseToWire(const Eigen::Isometry3d& pose, v1::Pose* wire) {
  AssignVector(pose.translation(), wire->mutable_position());
  const Eigen::Quaterniond rotation(pose.linear());
  wire->clear_quaternion();
  for (double value : {rotation.w(), rotation.x(), rotation.y(), rotation.z()}) wire->add_quaternion(value);
}

}  // namespace culinarycut::server
