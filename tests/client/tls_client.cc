// The C++ client against a server with TLS and bearer tokens: the right token drives a session,
// another token cannot see it, no token is UNAUTHENTICATED, and bad input names its field.
// Usage: tls_client ADDRESS PKI_DIR   (PKI_DIR from tests/support/make_test_pki.sh)
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include "culinarycut/client.h"

namespace cc = culinarycut::client;

namespace {

std::string Read(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

int failures = 0;

void Expect(bool ok, const std::string& what) {
  std::cout << (ok ? "ok    " : "FAIL  ") << what << "\n";
  if (!ok) ++failures;
}

// The gRPC code a call throws, or OK.
template <typename Call>
grpc::StatusCode CodeOf(Call call, std::string* field = nullptr) {
  try {
    call();
  } catch (const cc::RpcError& error) {
    if (field) *field = error.field();
    return error.code();
  }
  return grpc::StatusCode::OK;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: tls_client ADDRESS PKI_DIR\n";
    return 2;
  }
  const std::string address = argv[1], pki = argv[2];
  std::map<std::string, std::string> tokens;
  std::istringstream lines(Read(pki + "/tokens.txt"));
  for (std::string name, token; lines >> name >> token;) tokens[name] = token;

  cc::ConnectionOptions alice_options;
  alice_options.tls_root_certs_pem = Read(pki + "/ca.pem");
  alice_options.token = tokens.at("alice");
  cc::ConnectionOptions bob_options = alice_options;
  bob_options.token = tokens.at("bob");
  cc::ConnectionOptions no_token = alice_options;
  no_token.token.clear();
  no_token.call_timeout = std::chrono::seconds(5);

  cc::Client alice(address, alice_options), bob(address, bob_options), anonymous(address, no_token);
  auto session = alice.CreateSession();
  session->Reset(0);
  const cc::StepResult step = session->Step("pd_ee_delta_pose", {0, 0, 0, 0, 0, 0});
  Expect(step.observation.qpos.size() == 7, "a token over TLS steps a session");

  culinarycut::v1::ObserveRequest observe;
  observe.set_session_id(session->id());
  culinarycut::v1::ObserveResponse observed;
  const grpc::StatusCode other = CodeOf([&] {
    const grpc::Status status = bob.stub().Observe(bob.MakeContext().get(), observe, &observed);
    if (!status.ok()) throw cc::RpcError("Observe", status);
  });
  Expect(other == grpc::StatusCode::NOT_FOUND, "another token gets NOT_FOUND for the session");
  Expect(CodeOf([&] { anonymous.GetServerInfo(); }) == grpc::StatusCode::UNAUTHENTICATED,
         "no token is UNAUTHENTICATED");

  culinarycut::v1::SceneSpec scene;
  scene.add_objects()->set_food("cucumber");
  scene.mutable_objects(0)->set_scale(-2);
  scene.mutable_effects()->set_mpm(true);
  std::string field;
  const grpc::StatusCode bad = CodeOf([&] { alice.CreateSession(scene); }, &field);
  Expect(bad == grpc::StatusCode::INVALID_ARGUMENT && field == "scene.objects[0].scale",
         "bad input names its field as a structured detail (got '" + field + "')");
  return failures == 0 ? 0 : 1;
}
