// The one error type of the wire layer: a request field that cannot be read, named by its path
// (e.g. "scene.objects[1].scale"). The services turn it into INVALID_ARGUMENT (status.h).
#pragma once

#include <stdexcept>
#include <string>

namespace culinarycut::server {

class FieldError : public std::invalid_argument {
 public:
  // The message is "<field> <problem>", e.g. FieldError("scene.mpm.cfl", "must be in (0, 1]").
  FieldError(const std::string& field, const std::string& problem)
      : std::invalid_argument(field + " " + problem), field_(field) {}
  // An engine's error about this field, its message kept as the engine wrote it.
  static FieldError WithMessage(const std::string& field, const std::string& message) {
    return FieldError(field, message, WholeMessage{});
  }
  const std::string& field() const { return field_; }

 private:
  struct WholeMessage {};
  FieldError(const std::string& field, const std::string& message, WholeMessage)
      : std::invalid_argument(message), field_(field) {}
  std::string field_;
};

// Runs `check` (an engine validation of the value read from `field`); its task::TaskError, or any
// std::invalid_argument, becomes a FieldError naming that field.
template <typename Check>
void CheckField(const std::string& field, Check&& check) {
  try {
    check();
  } catch (const FieldError&) {
    throw;
  } catch (const std::invalid_argument& error) {
    throw FieldError::WithMessage(field, field + ": " + error.what());
  }
}

// A request for a feature this server does not have yet (UNIMPLEMENTED), named by its field.
class UnimplementedField : public std::runtime_error {
 public:
  UnimplementedField(const std::string& field, const std::string& feature)
      : std::runtime_error(field + ": " + feature +
                           " is not available in this server yet; GetServerInfo lists its capabilities") {}
};

}  // namespace culinarycut::server
