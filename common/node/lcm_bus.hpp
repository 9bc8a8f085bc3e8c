// Bus over LCM (lcm::LCM, any provider URL; udpm by default).
#pragma once

#include "common/node/bus.hpp"

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <exception>
#include <list>
#include <map>
#include <memory>
#include <string>
#include <unordered_set>

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
  /// Also write every message this bus publishes into the LCM event log `file` (created or
  /// replaced), as sent: a record that cannot miss what a separate lcm-logger might under load.
  /// Throws std::runtime_error naming the file if it cannot be created or written.
  void record_publishes(const std::string& file);
  /// Flush and close the record; throws naming the file on a write error (e.g. a full disk).
  void finish_record();
  /// Distinct messages this bus has published (sent to LCM), per channel: a resend of the same
  /// bytes counts once. What a complete recording of the run holds (scripts/run --lcm-log checks
  /// lcm-logger's recording against the nodes' sums).
  std::map<std::string, long> published_counts() const;

 private:
  struct Sub {
    LcmBus* bus;
    RawHandler handler;
  };
  static void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Sub* sub);
  std::unique_ptr<lcm::LCM> lcm_;
  std::exception_ptr pending_;      // an exception thrown by a handler, rethrown by handle()
  std::list<Sub> subs_;  // stable addresses for LCM's context pointers
  void record(const std::string& channel, const void* data, int size);
  std::unique_ptr<lcm::LogFile> record_;
  std::string record_file_;
  std::int64_t record_events_ = 0;
  std::map<std::string, std::unordered_set<std::uint64_t>> published_;  // per channel: digests of the messages sent
};

}  // namespace rnav
