// Snapshots a client can hold but not forge: the engine's bytes behind an HMAC-SHA256 tag under a
// key only the server knows (random per process, or shared by servers through a key file), so a
// restored blob is one a trusted server wrote. The engine still range-checks every field anyway.
#pragma once

#include <string>

namespace culinarycut::server {

class SnapshotSeal {
 public:
  // A fresh random key (getrandom), or the bytes of `key_file` when it is given (at least 32).
  // Throws std::runtime_error naming the file when it cannot be read or is too short.
  explicit SnapshotSeal(const std::string& key_file = "");

  std::string Seal(const std::string& snapshot) const;
  // The engine's bytes; throws FieldError("snapshot", ...) for a blob this key did not seal.
  std::string Open(const std::string& sealed) const;

 private:
  std::string key_;
};

}  // namespace culinarycut::server
