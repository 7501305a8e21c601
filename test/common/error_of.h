// The message of the ConfigError a call throws ("" when it throws none): for tests of error
// messages.
#pragma once

#include <functional>
#include <string>

#include "params/schema/field.h"

namespace scw {

inline std::string ErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace scw
