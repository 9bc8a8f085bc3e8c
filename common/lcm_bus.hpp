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
  /// @param url  LCM provider URL; empty = LCM_DEFAULT_URL or LCM's default. If it asks for
  ///             recv_buf_size=B [bytes], the kernel must grant B (net.core.rmem_max caps it):
  ///             otherwise std::runtime_error naming both (a smaller buffer drops bursts).
  explicit LcmBus(const std::string& url = "");
  /// Publish; a failed send (e.g. ENOBUFS) is retried kPublishAttempts times with doubling
  /// waits from 1 ms (about 1 s in all), then std::runtime_error naming channel and errno.
  void publish_raw(const std::string& channel, const void* data, int size) override;
  static constexpr int kPublishAttempts = 10;
  /// [bytes] The receive buffer the kernel grants a UDP socket that asks for `requested`.
  static long granted_receive_buffer(long requested);
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
