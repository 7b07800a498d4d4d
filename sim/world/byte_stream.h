// Little helpers that write plain values to a byte string and read them back with bounds checks:
// the snapshot format. A short or malformed buffer throws SnapshotError, never reads past the end.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim/world/snapshot.h"

namespace culinarycut {

class ByteWriter {
 public:
  template <typename T>
  void Put(const T& value) { bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T)); }
  void PutVector(const Eigen::VectorXd& v) {
    Put(static_cast<std::uint32_t>(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), sizeof(double) * v.size());
  }
  template <typename T>
  void PutArray(const std::vector<T>& values) {
    Put(static_cast<std::uint64_t>(values.size()));
    bytes_.append(reinterpret_cast<const char*>(values.data()), sizeof(T) * values.size());
  }
  std::size_t size() const { return bytes_.size(); }
  std::string Take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T Get() {
    Need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  // `name` names the field in the error.
  Eigen::VectorXd GetVector(std::uint32_t expected_size, const std::string& name) {
    const auto size = Get<std::uint32_t>();
    if (size != expected_size) throw SnapshotError("corrupt: " + name + " has the wrong length");
    Eigen::VectorXd v(size);
    Need(sizeof(double) * size);
    std::memcpy(v.data(), bytes_.data() + offset_, sizeof(double) * size);
    offset_ += sizeof(double) * size;
    return v;
  }
  // A vector of exactly `expected_size` plain values; `name` names the field in the error.
  template <typename T>
  std::vector<T> GetArray(std::uint64_t expected_size, const std::string& name) {
    if (Get<std::uint64_t>() != expected_size) throw SnapshotError("corrupt: " + name + " has the wrong length");
    Need(sizeof(T) * expected_size);
    std::vector<T> values(expected_size);
    std::memcpy(values.data(), bytes_.data() + offset_, sizeof(T) * expected_size);
    offset_ += sizeof(T) * expected_size;
    return values;
  }
  bool AtEnd() const { return offset_ == bytes_.size(); }

 private:
  void Need(size_t n) const {
    if (offset_ + n > bytes_.size()) throw SnapshotError("snapshot is truncated");
  }
  const std::string& bytes_;
  size_t offset_ = 0;
};

}  // namespace culinarycut
