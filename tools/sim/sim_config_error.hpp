// The one error type of the simulator's configuration (scenes, motions,
// scenarios): the message always names the file, the key path and why.
#pragma once

#include <stdexcept>

namespace tumble::sim {

struct SimConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace tumble::sim
