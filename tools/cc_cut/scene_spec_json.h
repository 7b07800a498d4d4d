// The server's SceneSpec in its protobuf JSON form (field names as in scene.proto, or their
// lowerCamel JSON names). Reading first checks every key and type against the message's
// descriptor, so an error names the field the way the server does: "scene.objects[0].scale:
// expected a number, got a string".
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "culinarycut/v1/scene.pb.h"

namespace culinarycut::cc_cut {

// `path` prefixes every field name in messages ("scene"). Throws std::invalid_argument.
v1::SceneSpec SceneSpecFromJson(const nlohmann::json& value, const std::string& path);

// With proto field names and every scalar written out, zeros included.
nlohmann::json SceneSpecToJson(const v1::SceneSpec& spec);
// Any message so, e.g. the ServerInfo fields `cc-cut --presets` prints.
nlohmann::json MessageToJson(const google::protobuf::Message& message);

}  // namespace culinarycut::cc_cut
