// The gRPC status of every situation the services share, so one situation always gets the same
// code and message: unknown sessions, sessions not reset or broken, and every exception the
// engine or the wire layer can throw.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "server/session_manager.h"

namespace culinarycut::server {

// A message safe to send and print: bytes that are not printable ASCII are escaped (\xNN, so a NUL
// no longer empties it), and past 1,000 characters it is cut with a count of what was left out, so
// an echoed megabyte of input never reaches the client.
std::string SafeMessage(const std::string& message);

// Every status the server sends goes through here (the message made safe).
inline grpc::Status MakeStatus(grpc::StatusCode code, const std::string& message) {
  return grpc::Status(code, SafeMessage(message));
}

inline grpc::Status InvalidArgument(const std::string& message) {
  return MakeStatus(grpc::StatusCode::INVALID_ARGUMENT, message);
}

// INVALID_ARGUMENT naming its field explicitly: the path rides in the status's details to the field
// interceptor (field_detail.h), which sends it as trailing metadata and clears the details, so even a
// one-word field ("snapshot", "split") reaches the client without parsing the message.
inline grpc::Status InvalidField(const std::string& field, const std::string& message) {
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, SafeMessage(message), SafeMessage(field));
}

// FAILED_PRECONDITION for a call that needs an episode on a session never reset.
grpc::Status NotReset(const Session& session);

// FAILED_PRECONDITION for a call that needs a consistent state on a session whose last Step failed.
grpc::Status Broken(const Session& session);

// Whether the client has given up on the call: cancelled, past its deadline, or the server is
// shutting down.
bool CallAbandoned(const grpc::ServerContext& context);

// DEADLINE_EXCEEDED or CANCELLED for a call abandoned before its work was applied.
grpc::Status NotApplied(const grpc::ServerContext& context);

// INVALID_ARGUMENT for an empty id, NOT_FOUND when the id names no live session of the caller's
// (another principal's session is answered as if it did not exist).
grpc::Status FindSession(SessionManager* sessions, const grpc::ServerContext& context, const std::string& session_id,
                         std::shared_ptr<Session>* session);

// The status of the exception being handled (call inside a catch block): the wire's FieldError,
// the engine's SceneError, SnapshotError and task::TaskError -> INVALID_ARGUMENT; UnimplementedField
// -> UNIMPLEMENTED; render::RenderError -> INTERNAL (the state is intact); anything else ->
// INTERNAL with its message. Never UNKNOWN.
grpc::Status StatusFromCurrentException();

// Runs `body` (returning grpc::Status) and turns any exception into its status.
template <typename Body>
grpc::Status Guarded(Body&& body) {
  try {
    return body();
  } catch (...) {
    return StatusFromCurrentException();
  }
}

}  // namespace culinarycut::server
