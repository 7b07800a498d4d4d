#include "tools/cc_cut/scene_spec_json.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>

#include "tools/cc_cut/json_object_reader.h"

namespace culinarycut::cc_cut {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using nlohmann::json;

void CheckMessage(const Descriptor& message, const json& value, const std::string& path);

std::string FieldNames(const Descriptor& message) {
  std::string names;
  for (int i = 0; i < message.field_count(); ++i) {
    names += (names.empty() ? "" : ", ") + message.field(i)->name();
  }
  return names;
}

// A field by its proto name or its lowerCamel JSON name, as the protobuf JSON parser accepts both.
const FieldDescriptor* FindField(const Descriptor& message, const std::string& key) {
  if (const FieldDescriptor* field = message.FindFieldByName(key)) return field;
  for (int i = 0; i < message.field_count(); ++i) {
    if (message.field(i)->json_name() == key) return message.field(i);
  }
  return nullptr;
}

// Proto3 JSON writes 64-bit integers as strings of digits; both forms read back.
bool IsIntegerString(const json& value, bool allow_sign) {
  if (!value.is_string()) return false;
  std::string text = value.get<std::string>();
  if (allow_sign && !text.empty() && text[0] == '-') text.erase(0, 1);
  return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

// One value of `field` (an element, for a repeated field).
void CheckValue(const FieldDescriptor& field, const json& value, const std::string& name) {
  const auto expect = [&](bool ok, const std::string& what) {
    if (!ok) FailField(name, "expected " + what + ", got " + JsonTypeName(value));
  };
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_MESSAGE:
      expect(value.is_object(), "an object");
      CheckMessage(*field.message_type(), value, name);
      return;
    case FieldDescriptor::CPPTYPE_STRING:
      expect(value.is_string(), "a string");
      return;
    case FieldDescriptor::CPPTYPE_BOOL:
      expect(value.is_boolean(), "true or false");
      return;
    case FieldDescriptor::CPPTYPE_DOUBLE:
    case FieldDescriptor::CPPTYPE_FLOAT:
      expect(value.is_number(), "a number");
      return;
    case FieldDescriptor::CPPTYPE_UINT32:
      expect(value.is_number_unsigned() && value.get<std::uint64_t>() <= std::numeric_limits<std::uint32_t>::max(),
             "an integer in [0, 4294967295]");
      return;
    case FieldDescriptor::CPPTYPE_UINT64:
      expect(value.is_number_unsigned() || IsIntegerString(value, false), "an integer >= 0");
      return;
    case FieldDescriptor::CPPTYPE_INT32:
      expect(value.is_number_integer() && value.get<std::int64_t>() >= std::numeric_limits<std::int32_t>::min() &&
                 value.get<std::int64_t>() <= std::numeric_limits<std::int32_t>::max(),
             "a 32-bit integer");
      return;
    case FieldDescriptor::CPPTYPE_INT64:
      expect(value.is_number_integer() || IsIntegerString(value, true), "an integer");
      return;
    case FieldDescriptor::CPPTYPE_ENUM:
      expect(value.is_string() || value.is_number_integer(), "an enum name");
      return;
  }
}

void CheckMessage(const Descriptor& message, const json& value, const std::string& path) {
  if (!value.is_object()) FailField(path, "expected an object, got " + JsonTypeName(value));
  for (const auto& item : value.items()) {
    const std::string name = path + "." + item.key();
    const FieldDescriptor* field = FindField(message, item.key());
    if (field == nullptr) FailField(name, "unknown field (" + message.name() + " has " + FieldNames(message) + ")");
    const json& member = item.value();
    if (field->is_map()) {
      if (!member.is_object()) FailField(name, "expected an object, got " + JsonTypeName(member));
      const FieldDescriptor& map_value = *field->message_type()->map_value();
      for (const auto& entry : member.items()) CheckValue(map_value, entry.value(), name + "." + entry.key());
    } else if (field->is_repeated()) {
      if (!member.is_array()) FailField(name, "expected an array, got " + JsonTypeName(member));
      for (std::size_t i = 0; i < member.size(); ++i) {
        CheckValue(*field, member[i], name + "[" + std::to_string(i) + "]");
      }
    } else {
      CheckValue(*field, member, name);
    }
  }
}

}  // namespace

v1::SceneSpec SceneSpecFromJson(const json& value, const std::string& path) {
  CheckMessage(*v1::SceneSpec::descriptor(), value, path);
  v1::SceneSpec spec;
  const auto status = google::protobuf::util::JsonStringToMessage(value.dump(), &spec);
  if (!status.ok()) {
    // Not expected after the check above; protobuf's message starts with "(field.path)".
    std::string message(status.message());
    if (!message.empty() && message[0] == '(') {
      const std::size_t close = message.find(')');
      if (close != std::string::npos) {
        FailField(path + "." + message.substr(1, close - 1), message.substr(std::min(close + 2, message.size())));
      }
    }
    FailField(path, message);
  }
  return spec;
}

json MessageToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string text;
  const auto status = google::protobuf::util::MessageToJsonString(message, &text, options);
  if (!status.ok()) {
    throw std::runtime_error("cannot write " + message.GetTypeName() + " as JSON: " + std::string(status.message()));
  }
  return json::parse(text);
}

json SceneSpecToJson(const v1::SceneSpec& spec) { return MessageToJson(spec); }

}  // namespace culinarycut::cc_cut
