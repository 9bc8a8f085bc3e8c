// Bus over LCM (lcm::LCM, any provider URL; udpm by default).
#pragma once

#include "bus.hpp"

#include <lcm/lcm-cpp.hpp>

#include <list>
#include <exception>
#include <memory>

namespace rnav {

class LcmBus : public Bus {
 public:
  /// @param url  LCM provider URL; empty = LCM_DEFAULT_URL or LCM's default.
  explicit LcmBus(const std::string& url = "");
  void publish_raw(const std::string& channel, const void* data, int size) override;
  void subscribe_raw(const std::string& channel, RawHandler handler) override;
  /// Wait up to timeout_ms for messages and dispatch them; returns false on timeout.
  bool handle(int timeout_ms);

 private:
  struct Sub {
    LcmBus* bus;
    RawHandler handler;
  };
  static void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Sub* sub);
  std::unique_ptr<lcm::LCM> lcm_;
  std::exception_ptr pending_;      // an exception thrown by a handler, rethrown by handle()
  std::list<Sub> subs_;  // stable addresses for LCM's context pointers
};

}  // namespace rnav
