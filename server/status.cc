#include "server/status.h"

#include "server/access_control.h"

#include <chrono>
#include <cstdio>

#include <spdlog/spdlog.h>

#include "server/wire/field_error.h"
#include "sim/render/render_error.h"
#include "sim/task/cut_spec.h"
#include "sim/world/model.h"
#include "sim/world/snapshot.h"

namespace culinarycut::server {

grpc::Status NotReset(const Session& session) {
  return MakeStatus(grpc::StatusCode::FAILED_PRECONDITION,
                      "session " + session.id +
                          " has not been reset; call Reset before Step, Observe, SaveSnapshot or "
                          "StartOracle");
}

grpc::Status Broken(const Session& session) {
  return MakeStatus(grpc::StatusCode::FAILED_PRECONDITION,
                      "session " + session.id + " is broken: " + session.broken_reason +
                          "; call Reset, or RestoreSnapshot with a snapshot taken before, to go on");
}

std::string SafeMessage(const std::string& message) {
  constexpr std::size_t kMaxLength = 1000;
  std::string safe;
  std::size_t used = 0;
  for (; used < message.size() && safe.size() < kMaxLength; ++used) {
    const unsigned char c = static_cast<unsigned char>(message[used]);
    if (c >= 0x20 && c < 0x7f) {
      safe += static_cast<char>(c);
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", c);
      safe += escaped;
    }
  }
  if (used < message.size()) safe += "... (" + std::to_string(message.size() - used) + " more characters)";
  return safe;
}

bool CallAbandoned(const grpc::ServerContext& context) {
  return context.IsCancelled() || std::chrono::system_clock::now() > context.deadline();
}

grpc::Status NotApplied(const grpc::ServerContext& context) {
  const bool late = std::chrono::system_clock::now() > context.deadline();
  return grpc::Status(late ? grpc::StatusCode::DEADLINE_EXCEEDED : grpc::StatusCode::CANCELLED,
                      std::string(late ? "the call's deadline passed" : "the call was cancelled") +
                          " before the step finished; nothing of it was applied");
}

grpc::Status FindSession(SessionManager* sessions, const grpc::ServerContext& context, const std::string& session_id,
                         std::shared_ptr<Session>* session) {
  if (session_id.empty()) return InvalidField("session_id", "session_id is empty; pass the id CreateSession returned");
  *session = sessions->Find(session_id, CallerPrincipal(context));  // ownership before the idle timer
  if (!*session) {
    return MakeStatus(grpc::StatusCode::NOT_FOUND,
                        "no session '" + session_id.substr(0, 64) + (session_id.size() > 64 ? "...'" : "'") +
                            ": it was closed, reclaimed after being idle, or never existed");
  }
  return grpc::Status::OK;
}

grpc::Status StatusFromCurrentException() {
  try {
    throw;
  } catch (const FieldError& error) {
    return InvalidField(error.field(), error.what());
  } catch (const UnimplementedField& error) {
    return MakeStatus(grpc::StatusCode::UNIMPLEMENTED, error.what());
  } catch (const SceneError& error) {
    return InvalidArgument(error.what());
  } catch (const SnapshotError& error) {
    return InvalidField("snapshot", std::string("snapshot: ") + error.what());
  } catch (const task::TaskError& error) {
    return InvalidArgument(error.what());
  } catch (const render::RenderError& error) {
    spdlog::error("rendering failed: {}", error.what());
    return MakeStatus(grpc::StatusCode::INTERNAL,
                        std::string("rendering the cameras failed: ") + error.what() +
                            "; the simulation state is intact (Observe retries the images)");
  } catch (const std::exception& error) {
    spdlog::error("internal error: {}", error.what());
    return MakeStatus(grpc::StatusCode::INTERNAL, std::string("internal error: ") + error.what());
  } catch (...) {
    return MakeStatus(grpc::StatusCode::INTERNAL, "internal error of an unknown kind");
  }
}

}  // namespace culinarycut::server
