// Conversions between Python values and the renderer's: numpy arrays that own
// their buffers, and rt messages given serialized (bytes) or as JSON (str).
#pragma once

#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "util/proto_limits.h"

namespace rtcore {

namespace nb = nanobind;

// A numpy array that takes over `values` without copying them.
template <class T>
nb::ndarray<nb::numpy, T> to_numpy(std::vector<T>&& values, std::initializer_list<size_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return nb::ndarray<nb::numpy, T>(owned->data(), shape, owner);
}

// bytes: the serialized message; str: its JSON form; None: all defaults.
// Read, not checked: what takes the message checks it once (the Renderer
// applies the schema's limits to its camera and settings).
inline void read_message(const nb::handle& value, google::protobuf::Message& message, const char* path) {
    const std::string& type = message.GetDescriptor()->full_name();
    if (value.is_none()) {
    } else if (nb::isinstance<nb::bytes>(value)) {
        const auto data = nb::borrow<nb::bytes>(value);
        if (!message.ParseFromArray(data.c_str(), int(data.size())))
            throw std::invalid_argument(std::string(path) + ": not a serialized " + type);
    } else if (nb::isinstance<nb::str>(value)) {
        rt::read_json_message(nb::borrow<nb::str>(value).c_str(), message, path);
    } else {
        throw std::invalid_argument(std::string(path) + ": expected bytes (serialized " + type +
                                    ") or str (its JSON form)");
    }
}

template <class Message>
Message read_message(const nb::handle& value, const char* path) {
    Message message;
    read_message(value, message, path);
    return message;
}

// An empty message of the rt type named `type_name` (e.g. "rt.JobRequest").
std::unique_ptr<google::protobuf::Message> new_message(const std::string& type_name);

template <class Message>
nb::bytes to_bytes(const Message& message) {
    const std::string data = message.SerializeAsString();
    return nb::bytes(data.data(), data.size());
}

}  // namespace rtcore
