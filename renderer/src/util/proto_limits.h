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
// std::invalid_argument naming the field path, e.g. "settings.width: 0 is
// below the minimum 1".
void apply_limits(google::protobuf::Message& message, std::string_view path);

// Parses the JSON form of a message (unknown fields are an error), then applies
// its limits. Throws std::invalid_argument naming `path` and the problem.
void parse_json_message(std::string_view json, google::protobuf::Message& message,
                        std::string_view path);

}  // namespace rt
