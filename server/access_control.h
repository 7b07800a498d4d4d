// Who may call the server: TLS (a server certificate, optionally verified client certificates) and
// bearer tokens, and the principal a call comes from, which owns the sessions it creates.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>
#include <grpcpp/security/auth_metadata_processor.h>

namespace culinarycut::server {

struct AccessOptions {
  std::string tls_cert_file;       // PEM server certificate chain; empty: no TLS
  std::string tls_key_file;        // PEM private key of the certificate
  std::string tls_client_ca_file;  // PEM CA bundle: clients must present a certificate it signed
  std::string token_file;          // one token per line ("name token", or the token alone); needs TLS
};

// Bearer tokens ("authorization: Bearer <token>") checked on every call; a call with a known token
// carries the token's name as its principal. Compared in constant time.
class TokenAuthenticator : public grpc::AuthMetadataProcessor {
 public:
  explicit TokenAuthenticator(const std::string& token_file);
  bool IsBlocking() const override { return false; }  // a table lookup: no need for its own thread
  grpc::Status Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                       OutputMetadata* consumed_auth_metadata, OutputMetadata* response_metadata) override;
  std::size_t size() const { return tokens_.size(); }

 private:
  struct Token {
    std::string name;
    std::string secret;
  };
  std::vector<Token> tokens_;
};

// TLS with the tokens checked, or plaintext when no certificate is given. Throws std::runtime_error
// naming the flag whose file cannot be read or makes no sense alone.
std::shared_ptr<grpc::ServerCredentials> MakeServerCredentials(const AccessOptions& options);

// Whether calls are authenticated (tokens or client certificates), so sessions have owners.
bool Authenticates(const AccessOptions& options);

// The caller: a token's name, else a client certificate's SHA-256 fingerprint (its subject only where gRPC
// gives no certificate), else "" (anyone who reaches the port, e.g. on loopback without authentication).
std::string CallerPrincipal(const grpc::ServerContext& context);

}  // namespace culinarycut::server
