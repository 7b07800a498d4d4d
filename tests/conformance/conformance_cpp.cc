// The conformance suite through the C++ client (cases.json; the Python runner is conformance.py).
// Usage: conformance_cpp CASES.json HOST:PORT; exits 1 naming each failure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <string>

#include <google/protobuf/util/json_util.h>
#include <nlohmann/json.hpp>

#include "culinarycut/client.h"

namespace {

using nlohmann::json;
using culinarycut::client::Client;
namespace v1 = culinarycut::v1;

struct Reply {
  std::string code = "OK";
  std::string message;
  std::string field;  // the culinarycut-field trailing metadata of an error
  json body = json::object();
};

std::string CodeName(grpc::StatusCode code) {
  static const std::map<grpc::StatusCode, std::string> names = {
      {grpc::StatusCode::OK, "OK"}, {grpc::StatusCode::CANCELLED, "CANCELLED"},
      {grpc::StatusCode::INVALID_ARGUMENT, "INVALID_ARGUMENT"}, {grpc::StatusCode::DEADLINE_EXCEEDED, "DEADLINE_EXCEEDED"},
      {grpc::StatusCode::NOT_FOUND, "NOT_FOUND"}, {grpc::StatusCode::FAILED_PRECONDITION, "FAILED_PRECONDITION"},
      {grpc::StatusCode::RESOURCE_EXHAUSTED, "RESOURCE_EXHAUSTED"}, {grpc::StatusCode::UNIMPLEMENTED, "UNIMPLEMENTED"},
      {grpc::StatusCode::INTERNAL, "INTERNAL"}, {grpc::StatusCode::UNAVAILABLE, "UNAVAILABLE"}};
  const auto it = names.find(code);
  return it == names.end() ? "CODE_" + std::to_string(code) : it->second;
}

// Calls one method with a request given as protobuf JSON; the reply comes back as JSON.
template <typename Request, typename Response, typename Method>
Reply Invoke(Client& client, const json& request_json, Method method) {
  Request request;
  const auto parsed = google::protobuf::util::JsonStringToMessage(request_json.dump(), &request);
  if (!parsed.ok()) return Reply{"BAD_CASE", "request does not parse: " + parsed.ToString(), {}};
  Response response;
  const auto context = client.MakeContext();
  const grpc::Status status = method(context.get(), request, &response);
  Reply reply;
  reply.code = CodeName(status.error_code());
  reply.message = status.error_message();
  const auto trailing = context->GetServerTrailingMetadata();
  if (const auto it = trailing.find("culinarycut-field"); it != trailing.end()) {
    reply.field.assign(it->second.data(), it->second.size());
  }
  if (status.ok()) {
    google::protobuf::util::JsonPrintOptions options;
    options.preserve_proto_field_names = true;
    options.always_print_primitive_fields = true;
    std::string text;
    (void)google::protobuf::util::MessageToJsonString(response, &text, options);
    reply.body = json::parse(text);
  }
  return reply;
}

using Call = std::function<Reply(Client&, const json&)>;

std::map<std::string, Call> Calls() {
  // One entry per method the cases use: the stub's method with its request and response types.
#define CULINARYCUT_CALL(stub, Name, Request, Response)                                                         \
  {#Name, [](Client& c, const json& r) {                                                                          \
     return Invoke<v1::Request, v1::Response>(c, r, [&c](grpc::ClientContext* x, const v1::Request& q, v1::Response* p) { \
       return c.stub().Name(x, q, p);                                                                             \
     });                                                                                                          \
   }}
  return {
      CULINARYCUT_CALL(stub, GetServerInfo, GetServerInfoRequest, ServerInfo),
      CULINARYCUT_CALL(stub, CreateSession, CreateSessionRequest, CreateSessionResponse),
      CULINARYCUT_CALL(stub, Reset, ResetRequest, ResetResponse),
      CULINARYCUT_CALL(stub, Step, StepRequest, StepResponse),
      CULINARYCUT_CALL(stub, Observe, ObserveRequest, ObserveResponse),
      CULINARYCUT_CALL(stub, CloseSession, CloseSessionRequest, CloseSessionResponse),
      CULINARYCUT_CALL(stub, SaveSnapshot, SaveSnapshotRequest, SaveSnapshotResponse),
      CULINARYCUT_CALL(stub, RestoreSnapshot, RestoreSnapshotRequest, RestoreSnapshotResponse),
      CULINARYCUT_CALL(stub, GetSessionStats, GetSessionStatsRequest, SessionStats),
      CULINARYCUT_CALL(tasks_stub, ParseInstruction, ParseInstructionRequest, ParseInstructionResponse),
      CULINARYCUT_CALL(tasks_stub, GenerateInstructions, GenerateInstructionsRequest, GenerateInstructionsResponse),
  };
#undef CULINARYCUT_CALL
}

const json* AtPath(const json& body, const std::string& path) {
  const json* node = &body;
  std::size_t start = 0;
  while (start <= path.size() && !path.empty()) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return node;
}

// Replaces "$name.path" strings anywhere in a request by the saved reply's value there.
json Resolve(const json& value, const std::map<std::string, json>& saved) {
  if (value.is_object() || value.is_array()) {
    json out = value;
    for (auto& item : out.items()) item.value() = Resolve(item.value(), saved);
    return out;
  }
  if (value.is_string() && !value.get<std::string>().empty() && value.get<std::string>()[0] == '$') {
    const std::string reference = value.get<std::string>().substr(1);
    const std::size_t dot = reference.find('.');
    const json* found = AtPath(saved.at(reference.substr(0, dot)), dot == std::string::npos ? "" : reference.substr(dot + 1));
    return found ? *found : json();
  }
  return value;
}

// proto3 JSON writes 64-bit integers as strings; numbers compare within a relative 1e-9.
bool Same(const json& actual, const json& expected) {
  if (expected.is_number()) {
    double value = 0.0;
    if (actual.is_number()) value = actual.get<double>();
    else if (actual.is_string()) value = std::stod(actual.get<std::string>());
    else return false;
    return std::abs(value - expected.get<double>()) <= 1e-9 * std::max(1.0, std::abs(expected.get<double>()));
  }
  return actual == expected;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: conformance_cpp CASES.json HOST:PORT\n");
    return 2;
  }
  std::ifstream file(argv[1]);
  const json table = json::parse(file);
  Client client(argv[2], std::chrono::seconds(60));
  const std::map<std::string, Call> calls = Calls();
  int failures = 0;
  auto fail = [&failures](const std::string& where, const std::string& what) {
    std::printf("FAILED: %s: %s\n", where.c_str(), what.c_str());
    ++failures;
  };
  for (const json& test : table["cases"]) {
    std::map<std::string, json> saved;
    int index = 0;
    for (const json& call : test["calls"]) {
      const std::string where = test["name"].get<std::string>() + " / call " + std::to_string(index++) + " " +
                                call["call"].get<std::string>();
      const Reply reply = calls.at(call["call"].get<std::string>())(client, Resolve(call["request"], saved));
      if (call.contains("save")) saved[call["save"].get<std::string>()] = reply.body;
      const json expect = call.value("expect", json{{"code", "OK"}});
      if (reply.code != expect.value("code", "OK")) {
        fail(where, "code " + reply.code + " (" + reply.message + "), expected " + expect.value("code", "OK"));
        break;
      }
      if (expect.contains("message_contains") &&
          reply.message.find(expect["message_contains"].get<std::string>()) == std::string::npos) {
        fail(where, "message '" + reply.message + "' lacks '" + expect["message_contains"].get<std::string>() + "'");
      }
      if (expect.contains("field") && reply.field != expect["field"].get<std::string>()) {
        fail(where, "field detail '" + reply.field + "', expected '" + expect["field"].get<std::string>() + "'");
      }
      const json fields = expect.value("fields", json::object());  // named: items() must not outlive it
      for (const auto& [path, value] : fields.items()) {
        const json* actual = AtPath(reply.body, path);
        if (!actual || !Same(*actual, value)) fail(where, path + " = " + (actual ? actual->dump() : "<missing>") + ", expected " + value.dump());
      }
      const json contains = expect.value("contains", json::object());
      for (const auto& [path, values] : contains.items()) {
        const json* actual = AtPath(reply.body, path);
        for (const json& value : values) {
          if (!actual || std::find(actual->begin(), actual->end(), value) == actual->end()) fail(where, path + " lacks " + value.dump());
        }
      }
    }
  }
  std::printf("C++ conformance: %zu cases, %d failures\n", table["cases"].size(), failures);
  return failures == 0 ? 0 : 1;
}
