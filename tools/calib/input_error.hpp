// A bench input that cannot be used: one line naming the file (and line or
// key) and what is wrong. The bench loop reports it for that run and goes on.
#pragma once

#include <stdexcept>

namespace tumble::calib {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tumble::calib
