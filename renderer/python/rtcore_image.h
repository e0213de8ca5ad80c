// The image functions of the rtcore module.
#pragma once

#include <nanobind/nanobind.h>

namespace rtcore {

void bind_images(nanobind::module_& m);

}  // namespace rtcore
