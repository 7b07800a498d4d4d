#include "server/access_control.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <openssl/crypto.h>
#include <openssl/evp.h>

namespace culinarycut::server {
namespace {

constexpr char kPrincipalProperty[] = "culinarycut_principal";
constexpr char kBearerPrefix[] = "Bearer ";

std::string ReadFile(const std::string& path, const std::string& flag) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error(flag + " " + path + ": cannot be read");
  std::ostringstream text;
  text << file.rdbuf();
  if (text.str().empty()) throw std::runtime_error(flag + " " + path + ": the file is empty");
  return text.str();
}

bool SameSecret(const std::string& a, const std::string& b) {
  return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

}  // namespace

TokenAuthenticator::TokenAuthenticator(const std::string& token_file) {
  std::istringstream lines(ReadFile(token_file, "--token-file"));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string first, second, extra;
    fields >> first >> second >> extra;
    if (first.empty()) continue;
    if (!extra.empty()) throw std::runtime_error("--token-file: a line holds more than \"name token\"");
    Token token = second.empty() ? Token{"token-" + std::to_string(tokens_.size() + 1), first} : Token{first, second};
    if (token.secret.size() < 16) {
      throw std::runtime_error("--token-file: token '" + token.name + "' is shorter than 16 characters; use e.g. "
                               "openssl rand -hex 32");
    }
    tokens_.push_back(std::move(token));
  }
  if (tokens_.empty()) throw std::runtime_error("--token-file " + token_file + ": no tokens in it");
}

grpc::Status TokenAuthenticator::Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                                         OutputMetadata* consumed_auth_metadata, OutputMetadata*) {
  const auto found = auth_metadata.find("authorization");
  if (found == auth_metadata.end()) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "this server needs a bearer token (authorization: Bearer <token>)");
  }
  const std::string value(found->second.data(), found->second.size());
  const std::string presented = value.rfind(kBearerPrefix, 0) == 0 ? value.substr(sizeof(kBearerPrefix) - 1) : "";
  for (const Token& token : tokens_) {
    if (!SameSecret(presented, token.secret)) continue;
    consumed_auth_metadata->insert(std::make_pair(std::string("authorization"), value));
    context->AddProperty(kPrincipalProperty, token.name);
    context->SetPeerIdentityPropertyName(kPrincipalProperty);
    return grpc::Status::OK;
  }
  return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, "unknown bearer token");
}

bool Authenticates(const AccessOptions& options) {
  return !options.token_file.empty() || !options.tls_client_ca_file.empty();
}

std::shared_ptr<grpc::ServerCredentials> MakeServerCredentials(const AccessOptions& options) {
  const bool tls = !options.tls_cert_file.empty() || !options.tls_key_file.empty();
  if (!tls) {
    if (!options.token_file.empty()) {
      throw std::runtime_error("--token-file needs --tls-cert and --tls-key: a bearer token sent in plaintext can be "
                               "read off the wire");
    }
    if (!options.tls_client_ca_file.empty()) throw std::runtime_error("--tls-client-ca needs --tls-cert and --tls-key");
    return grpc::InsecureServerCredentials();
  }
  if (options.tls_cert_file.empty() || options.tls_key_file.empty()) {
    throw std::runtime_error("TLS needs both --tls-cert and --tls-key");
  }
  grpc::SslServerCredentialsOptions ssl;
  ssl.pem_key_cert_pairs.push_back({ReadFile(options.tls_key_file, "--tls-key"),
                                    ReadFile(options.tls_cert_file, "--tls-cert")});
  if (!options.tls_client_ca_file.empty()) {
    ssl.pem_root_certs = ReadFile(options.tls_client_ca_file, "--tls-client-ca");
    ssl.client_certificate_request = GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY;
  }
  std::shared_ptr<grpc::ServerCredentials> credentials = grpc::SslServerCredentials(ssl);
  if (!options.token_file.empty()) {
    credentials->SetAuthMetadataProcessor(std::make_shared<TokenAuthenticator>(options.token_file));
  }
  return credentials;
}

// "x509_sha256:<hex>" of a PEM certificate: two certificates with the same subject are still two clients.
std::string CertificateFingerprint(const grpc::string_ref& pem) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(pem.data(), pem.size(), digest, &length, EVP_sha256(), nullptr) != 1) return "";
  std::ostringstream hex;
  hex << "x509_sha256:" << std::hex << std::setfill('0');
  for (unsigned int i = 0; i < length; ++i) hex << std::setw(2) << static_cast<int>(digest[i]);
  return hex.str();
}

std::string CallerPrincipal(const grpc::ServerContext& context) {
  const std::shared_ptr<const grpc::AuthContext> auth = context.auth_context();
  if (!auth) return "";
  const std::vector<grpc::string_ref> token = auth->FindPropertyValues(kPrincipalProperty);
  if (!token.empty()) {
    return std::string(kPrincipalProperty) + ":" + std::string(token.front().data(), token.front().size());
  }
  // Mutual TLS: the client is its certificate, by fingerprint (the PEM gRPC saw), not its subject.
  const std::vector<grpc::string_ref> certificate = auth->FindPropertyValues("x509_pem_cert");
  if (!certificate.empty()) {
    if (std::string fingerprint = CertificateFingerprint(certificate.front()); !fingerprint.empty()) return fingerprint;
  }
  for (const char* property : {"x509_subject", "x509_common_name"}) {
    const std::vector<grpc::string_ref> values = auth->FindPropertyValues(property);
    if (!values.empty()) return std::string(property) + ":" + std::string(values.front().data(), values.front().size());
  }
  return "";
}

}  // namespace culinarycut::server
