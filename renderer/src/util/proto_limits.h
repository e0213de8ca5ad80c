// The schema's own defaults and limits (proto/rt/options.proto), applied to any
// message by reflection, so the numbers live in one place: the .proto files.
#pragma once

#include <string>
#include <string_view>

#include <google/protobuf/message.h>

namespace rt {

// Fills absent optional fields that declare a default, then checks every field
// and sub-message against its limits, and every enum against the values its
// type names (an absent enum field is its zero value, the default). Throws
// std::invalid_argument naming the field path by the proto's field names, as
// API users write them, e.g. "settings.max_depth: 65 is above the maximum 64".
// An empty `path` names top-level fields alone ("scene_id: ...").
void apply_limits(google::protobuf::Message& message, std::string_view path);

// Parses the JSON form of a message (field names as written in the .proto or
// in lowerCamelCase; unknown fields are an error), without applying limits.
// Throws std::invalid_argument naming `path` and the problem.
void read_json_message(std::string_view json, google::protobuf::Message& message, std::string_view path);

// read_json_message, then apply_limits.
void parse_json_message(std::string_view json, google::protobuf::Message& message,
                        std::string_view path);

}  // namespace rt
