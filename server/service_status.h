// Status helpers every service shares, so one situation always gets the same code and message.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "server/session_manager.h"

namespace culinarycut::server {

inline grpc::Status InvalidArgument(const std::string& message) {
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message);
}

// FAILED_PRECONDITION for a call that needs an episode on a session never reset.
grpc::Status NotReset(const Session& session);

// INVALID_ARGUMENT for an empty id, NOT_FOUND when the id names no live session.
grpc::Status FindSession(SessionManager* sessions, const std::string& session_id,
                         std::shared_ptr<Session>* session);

}  // namespace culinarycut::server
