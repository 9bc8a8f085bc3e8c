// A free-running node: no lock-step clock; it reacts to messages as they come, driven by their
// own time stamps (see free_input.hpp), so a replayed log or a live feed can drive it.
#pragma once

#include <string>

namespace rnav {

class FreeNode {
 public:
  virtual ~FreeNode() = default;
  /// Messages taken in so far (the main's idle timer watches this count).
  long received() const { return received_; }
  /// The input has ended: decide and publish everything still waiting.
  virtual void flush() = 0;
  /// One line for the log: what was received, skipped and published.
  virtual std::string summary() const = 0;

 protected:
  long received_ = 0;
};

}  // namespace rnav
