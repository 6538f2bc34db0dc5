// The error of sluice render for a request that cannot be met.
#pragma once

#include <stdexcept>

namespace sluice::render {

// An unknown field, a malformed option, no frames, a time with no frame. Damaged frames raise
// sluice::FormatError and unreadable files sluice::IoError instead.
struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace sluice::render
