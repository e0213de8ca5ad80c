#include "util/proto_limits.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>

#include "rt/options.pb.h"

namespace rt {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

std::string format_number(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

[[noreturn]] void fail(std::string_view path, const std::string& problem) {
    throw std::invalid_argument(std::string(path) + ": " + problem);
}

bool is_numeric(const FieldDescriptor* field) {
    switch (field->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT:
        case FieldDescriptor::CPPTYPE_DOUBLE:
        case FieldDescriptor::CPPTYPE_INT32:
        case FieldDescriptor::CPPTYPE_INT64:
        case FieldDescriptor::CPPTYPE_UINT32:
        case FieldDescriptor::CPPTYPE_UINT64:
            return true;
        default:
            return false;
    }
}

double get_number(const Message& m, const Reflection* r, const FieldDescriptor* f, int index) {
    const bool repeated = f->is_repeated();
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT:
            return repeated ? r->GetRepeatedFloat(m, f, index) : r->GetFloat(m, f);
        case FieldDescriptor::CPPTYPE_DOUBLE:
            return repeated ? r->GetRepeatedDouble(m, f, index) : r->GetDouble(m, f);
        case FieldDescriptor::CPPTYPE_INT32:
            return repeated ? r->GetRepeatedInt32(m, f, index) : r->GetInt32(m, f);
        case FieldDescriptor::CPPTYPE_INT64:
            return double(repeated ? r->GetRepeatedInt64(m, f, index) : r->GetInt64(m, f));
        case FieldDescriptor::CPPTYPE_UINT32:
            return repeated ? r->GetRepeatedUInt32(m, f, index) : r->GetUInt32(m, f);
        case FieldDescriptor::CPPTYPE_UINT64:
            return double(repeated ? r->GetRepeatedUInt64(m, f, index) : r->GetUInt64(m, f));
        default:
            return 0.0;
    }
}

void set_number(Message& m, const Reflection* r, const FieldDescriptor* f, double v) {
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT: r->SetFloat(&m, f, float(v)); break;
        case FieldDescriptor::CPPTYPE_DOUBLE: r->SetDouble(&m, f, v); break;
        case FieldDescriptor::CPPTYPE_INT32: r->SetInt32(&m, f, int32_t(v)); break;
        case FieldDescriptor::CPPTYPE_INT64: r->SetInt64(&m, f, int64_t(v)); break;
        case FieldDescriptor::CPPTYPE_UINT32: r->SetUInt32(&m, f, uint32_t(v)); break;
        case FieldDescriptor::CPPTYPE_UINT64: r->SetUInt64(&m, f, uint64_t(v)); break;
        default: break;
    }
}

// A float field holds its value rounded to float, so its limits are compared
// rounded the same way: `max: 1e30` must admit the float nearest 1e30.
double limit_for(const FieldDescriptor* field, double limit) {
    return field->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT ? double(float(limit)) : limit;
}

void check_value(std::string_view path, double v, const FieldDescriptor* field, const Limits& limits) {
    if (!std::isfinite(v)) fail(path, "must be a finite number");
    if (limits.has_min() && v < limit_for(field, limits.min()))
        fail(path, format_number(v) + " is below the minimum " + format_number(limits.min()));
    if (limits.has_max() && v > limit_for(field, limits.max()))
        fail(path, format_number(v) + " is above the maximum " + format_number(limits.max()));
}

// Proto3 enums are open: binary input can carry numbers the schema never named.
void check_enum(std::string_view path, int value, const FieldDescriptor* field) {
    const auto* type = field->enum_type();
    if (type->FindValueByNumber(value)) return;
    std::string names;
    for (int i = 0; i < type->value_count(); ++i) names += (i ? ", " : "") + type->value(i)->name();
    fail(path, std::to_string(value) + " is not one of " + names);
}

}  // namespace

void apply_limits(Message& message, std::string_view path) {
    const auto* descriptor = message.GetDescriptor();
    const Reflection* reflection = message.GetReflection();
    for (int i = 0; i < descriptor->field_count(); ++i) {
        const FieldDescriptor* field = descriptor->field(i);
        const Limits& limits = field->options().GetExtension(rt::limits);
        const std::string field_path = path.empty() ? field->name() : std::string(path) + "." + field->name();

        if (field->is_repeated()) {
            const int size = reflection->FieldSize(message, field);
            if (size == 0 && limits.required()) fail(field_path, "is required");
            if (size != 0 && limits.count() != 0 && uint32_t(size) != limits.count())
                fail(field_path, "needs " + std::to_string(limits.count()) + " values, got " +
                                     std::to_string(size));
            for (int k = 0; k < size; ++k) {
                const std::string element = field_path + "[" + std::to_string(k) + "]";
                if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE)
                    apply_limits(*reflection->MutableRepeatedMessage(&message, field, k), element);
                else if (field->cpp_type() == FieldDescriptor::CPPTYPE_ENUM)
                    check_enum(element, reflection->GetRepeatedEnumValue(message, field, k), field);
                else if (is_numeric(field))
                    check_value(element, get_number(message, reflection, field, k), field, limits);
            }
            continue;
        }

        const bool present = !field->has_presence() || reflection->HasField(message, field);
        if (!present) {
            if (limits.required()) fail(field_path, "is required");
            if (limits.has_default_() && is_numeric(field))
                set_number(message, reflection, field, limits.default_());
            else
                continue;
        }
        if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE)
            apply_limits(*reflection->MutableMessage(&message, field), field_path);
        else if (field->cpp_type() == FieldDescriptor::CPPTYPE_ENUM)
            check_enum(field_path, reflection->GetEnumValue(message, field), field);
        else if (is_numeric(field))
            check_value(field_path, get_number(message, reflection, field, -1), field, limits);
    }
}

void read_json_message(std::string_view json, Message& message, std::string_view path) {
    google::protobuf::util::JsonParseOptions options;
    options.ignore_unknown_fields = false;
    const auto status = google::protobuf::util::JsonStringToMessage(
        google::protobuf::StringPiece(json.data(), json.size()), &message, options);
    if (!status.ok()) fail(path.empty() ? "body" : path, "invalid JSON: " + std::string(status.message()));
}

void parse_json_message(std::string_view json, Message& message, std::string_view path) {
    read_json_message(json, message, path);
    apply_limits(message, path);
}

}  // namespace rt
