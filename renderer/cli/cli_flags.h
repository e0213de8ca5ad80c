// rtrender's command line: its options, --help, and the parsing that turns
// argv into them. Apart from rtrender.cpp because most of it is reflection
// over rt.RenderSettings (a flag per field), which rendering never needs.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "rt/job.pb.h"
#include "rt/render.pb.h"

namespace rtrender {

// A command line that cannot be run as given: exit status 2, not 1.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::string scene;
    std::string output;
    std::string noisy;  // --noisy: the image before denoising, when it is denoised
    std::string settings_file;
    std::string camera_name;
    std::string camera_file;
    float ortho_height = 0.0f;  // --orthographic: above 0, the camera's projection overridden
    bool perspective = false;   // --perspective
    unsigned threads = 0;
    uint32_t tile_size = 32;
    bool quiet = false;
    bool debug_pixel = false;
    uint32_t debug_x = 0, debug_y = 0;
    std::vector<rt::AuxOutput> aux;  // auxiliary outputs, as extra EXR channels
    rt::RenderSettings flags;  // settings given as flags; they override the file
};

// The options argv gives, checked against each other; throws UsageError.
// -h or --help prints the help and exits with status 0.
Options parse_arguments(int argc, char** argv);

}  // namespace rtrender
