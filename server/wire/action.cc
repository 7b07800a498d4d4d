#include "server/wire/action.h"

#include "server/wire/field_error.h"
#include "server/wire/values.h"

namespace culinarycut::server {

ControlMode ControlModeFromWire(const std::string& name, const std::string& field) {
  if (name.empty()) return kDefaultControlMode;
  TextFromWire(name, field, 64);
  if (const std::optional<ControlMode> mode = ParseControlMode(name)) return *mode;
  std::string names;
  for (ControlMode mode : AllControlModes()) names += (names.empty() ? "" : ", ") + std::string(ControlModeName(mode));
  throw FieldError(field, "'" + name.substr(0, 64) + "' is unknown; use one of " + names);
}

Action ActionFromWire(const v1::Action& wire) {
  return Action{ControlModeFromWire(wire.control_mode(), "action.control_mode"),
                Eigen::Map<const Eigen::VectorXd>(wire.values().data(), wire.values_size())};
}

}  // namespace culinarycut::server
