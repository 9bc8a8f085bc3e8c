// The message of the ConfigError a piece of test code throws, for the tests of configuration
// and command-line errors (test_config, test_cli, test_datalink_link).
#pragma once

#include "common/io/config.hpp"

#include <string>

namespace rnav_test {

/// The message of the rnav::ConfigError thrown by f; "<no exception>" if none, "<other
/// exception>" if f throws anything else.
template <class F> std::string config_error(F&& f) {
  try {
    f();
  } catch (const rnav::ConfigError& e) {
    return e.what();
  } catch (...) {
    return "<other exception>";
  }
  return "<no exception>";
}

}  // namespace rnav_test
