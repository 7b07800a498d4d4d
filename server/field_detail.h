// Every INVALID_ARGUMENT names the field at fault: explicitly (InvalidField in status.h, e.g. every
// wire FieldError) or at the start of its message. This interceptor sends that path as trailing
// metadata "culinarycut-field", a structured detail clients expose (Python: CulinaryCutError.field;
// C++: RpcError::field()) without parsing messages.
#pragma once

#include <string>

#include <grpcpp/support/server_interceptor.h>

namespace culinarycut::server {

inline constexpr char kFieldMetadataKey[] = "culinarycut-field";

// The field path a message starts with ("scene.objects[0].scale is ..." -> "scene.objects[0].scale"),
// or "" when it starts with a plain word (a path has a '.', '[' or '_').
std::string LeadingFieldPath(const std::string& message);

class FieldDetailInterceptorFactory : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) override;
};

}  // namespace culinarycut::server
