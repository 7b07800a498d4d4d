#include "server/service_status.h"

namespace culinarycut::server {

grpc::Status NotReset(const Session& session) {
  return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                      "session " + session.id +
                          " has not been reset; call Reset before Step, Observe, SaveSnapshot or "
                          "StartOracle");
}

grpc::Status FindSession(SessionManager* sessions, const std::string& session_id,
                         std::shared_ptr<Session>* session) {
  if (session_id.empty()) return InvalidArgument("session_id is empty; pass the id CreateSession returned");
  *session = sessions->Find(session_id);
  if (!*session) {
    return grpc::Status(grpc::StatusCode::NOT_FOUND,
                        "no session '" + session_id +
                            "': it was closed, reclaimed after being idle, or never existed");
  }
  return grpc::Status::OK;
}

}  // namespace culinarycut::server
