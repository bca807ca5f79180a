// The library's own error type. Thrown inside, mapped to SsStatus at the API.
#pragma once
#include <stdexcept>
#include <string>

#include "subsplat/subsplat.h"

namespace subsplat {

class Error : public std::runtime_error {
 public:
  Error(SsStatus status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  SsStatus status() const { return status_; }

 private:
  SsStatus status_;
};

[[noreturn]] inline void fail(SsStatus status, const std::string& message) {
  throw Error(status, message);
}

inline void require(bool condition, const std::string& message) {
  if (!condition) fail(SS_INVALID_ARGUMENT, message);
}

}  // namespace subsplat
