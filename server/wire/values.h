// Small readers and writers every wire conversion shares: vectors, poses, matrices and pixel bytes,
// and the checks on single values. Readers throw FieldError naming the field.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <google/protobuf/repeated_field.h>

#include "culinarycut/v1/scene.pb.h"
#include "server/wire/field_error.h"

namespace culinarycut::server {

// Copies an Eigen vector into a repeated double field.
template <typename Vector>
void AssignVector(const Vector& values, google::protobuf::RepeatedField<double>* field) {
  field->Assign(values.data(), values.data() + values.size());
}

// Row-major copy of the top `rows` rows of an Eigen matrix into a repeated double field.
template <typename Matrix>
void AssignRowMajor(const Matrix& matrix, int rows, google::protobuf::RepeatedField<double>* field) {
  field->Clear();
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < matrix.cols(); ++c) field->Add(matrix(r, c));
  }
}

// Copies the raw bytes of a pixel array into a bytes field (little-endian on every platform we build for).
template <typename T>
void AssignBytes(const std::vector<T>& pixels, std::string* field) {
  field->assign(reinterpret_cast<const char*>(pixels.data()), pixels.size() * sizeof(T));
}

// A name or text from the wire: at most `max_length` bytes and no control characters (a NUL would
// cut every message that quotes it). UTF-8 beyond ASCII passes.
const std::string& TextFromWire(const std::string& value, const std::string& field, std::size_t max_length = 256);

// `value` must be finite.
double FiniteFromWire(double value, const std::string& field);
// `value` must be finite and in [low, high]; `unit` is appended to the bounds in the message.
double RangeFromWire(double value, double low, double high, const std::string& field, const std::string& unit = "");
// An unsigned count that must not exceed `high` (the engine checks the finer range).
int CountFromWire(std::uint64_t value, std::uint64_t high, const std::string& field);

Eigen::Vector3d Vector3FromWire(const google::protobuf::RepeatedField<double>& values, const std::string& field);
// A pose with a 3-vector position and a quaternion [w, x, y, z] of positive norm (normalised here).
Eigen::Isometry3d PoseFromWire(const v1::Pose& wire, const std::string& field);
void PoseToWire(const Eigen::Isometry3d& pose, v1::Pose* wire);

}  // namespace culinarycut::server
