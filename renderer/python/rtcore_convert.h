// Conversions between Python values and the renderer's: numpy arrays that own
// their buffers, and rt messages given serialized (bytes) or as JSON (str).
#pragma once

#include <initializer_list>
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
template <class Message>
Message read_message(const nb::handle& value, const char* path) {
    Message message;
    if (value.is_none()) {
    } else if (nb::isinstance<nb::bytes>(value)) {
        const auto data = nb::borrow<nb::bytes>(value);
        if (!message.ParseFromArray(data.c_str(), int(data.size())))
            throw std::invalid_argument(std::string(path) + ": not a serialized " + Message::descriptor()->full_name());
    } else if (nb::isinstance<nb::str>(value)) {
        rt::parse_json_message(nb::borrow<nb::str>(value).c_str(), message, path);
        return message;
    } else {
        throw std::invalid_argument(std::string(path) + ": expected bytes (serialized " +
                                    Message::descriptor()->full_name() + ") or str (its JSON form)");
    }
    rt::apply_limits(message, path);
    return message;
}

template <class Message>
nb::bytes to_bytes(const Message& message) {
    const std::string data = message.SerializeAsString();
    return nb::bytes(data.data(), data.size());
}

}  // namespace rtcore
