#include "server/field_detail.h"

#include <cctype>

namespace culinarycut::server {
namespace {

class FieldDetailInterceptor : public grpc::experimental::Interceptor {
 public:
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    using grpc::experimental::InterceptionHookPoints;
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS)) {
      const grpc::Status status = methods->GetSendStatus();
      if (status.error_code() == grpc::StatusCode::INVALID_ARGUMENT) {
        // An explicit field (InvalidField) rides in the details; otherwise the message's leading path.
        const bool explicit_field = !status.error_details().empty();
        const std::string field = explicit_field ? status.error_details() : LeadingFieldPath(status.error_message());
        if (!field.empty()) methods->GetSendTrailingMetadata()->emplace(kFieldMetadataKey, field);
        // The details were ours, not a serialised google.rpc.Status: never send them on the wire.
        if (explicit_field) methods->ModifySendStatus(grpc::Status(status.error_code(), status.error_message()));
      }
    }
    methods->Proceed();
  }
};

bool NameCharacter(char c) {
  return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_';
}

}  // namespace

std::string LeadingFieldPath(const std::string& message) {
  std::size_t end = 0;
  while (end < message.size()) {
    const char c = message[end];
    if (NameCharacter(c) || c == '.') {
      ++end;
    } else if (c == '[') {  // an index: digits then ']'
      std::size_t close = end + 1;
      while (close < message.size() && std::isdigit(static_cast<unsigned char>(message[close]))) ++close;
      if (close == end + 1 || close >= message.size() || message[close] != ']') break;
      end = close + 1;
    } else {
      break;
    }
  }
  std::string path = message.substr(0, end);
  while (!path.empty() && path.back() == '.') path.pop_back();  // the sentence's full stop
  const bool path_like = path.find_first_of(".[_") != std::string::npos;
  const bool ends_word = end == message.size() || message[end] == ' ' || message[end] == ':' || message[end] == ',' ||
                         message[end] == '(';
  return path_like && ends_word && !path.empty() && std::islower(static_cast<unsigned char>(path[0])) ? path : "";
}

grpc::experimental::Interceptor* FieldDetailInterceptorFactory::CreateServerInterceptor(
    grpc::experimental::ServerRpcInfo*) {
  return new FieldDetailInterceptor;
}

}  // namespace culinarycut::server
