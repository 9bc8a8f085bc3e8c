#include "common/node/lcm_bus.hpp"

#include <functional>
#include <string_view>

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <thread>
#include <utility>

namespace rnav {

long LcmBus::granted_receive_buffer(long requested) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) throw std::runtime_error(std::string("cannot open a UDP socket to check the receive buffer: ") + std::strerror(errno));
  const int want = static_cast<int>(std::min<long>(requested, std::numeric_limits<int>::max() / 2));
  int got = 0;
  socklen_t len = sizeof got;
  const bool ok = ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &want, sizeof want) == 0 &&
                  ::getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &got, &len) == 0;
  ::close(fd);
  if (!ok) throw std::runtime_error(std::string("cannot set a UDP receive buffer: ") + std::strerror(errno));
  return got / 2;  // Linux reports twice the granted size (its bookkeeping overhead)
}

LcmBus::LcmBus(const std::string& url) {
  // RNAV_RUN_ID: the run's id, drawn by scripts/run for all its processes (0 when unset)
  if (const char* id = std::getenv("RNAV_RUN_ID")) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(id, &end, 10);
    if (*id == '\0' || *end != '\0' || errno != 0 || v < 0)
      throw std::runtime_error(std::string("RNAV_RUN_ID must be an integer in 0 ... 2^63-1, got '") + id + "'");
    set_run_id(v);
  }
  // recv_buf_size=B in the URL: LCM asks for B with SO_RCVBUF, which the kernel silently caps at
  // net.core.rmem_max. Ask the same of a probe socket and refuse to run on less.
  const std::string effective = url.empty() ? (std::getenv("LCM_DEFAULT_URL") ? std::getenv("LCM_DEFAULT_URL") : "") : url;
  const auto at = effective.find("recv_buf_size=");
  if (at != std::string::npos) {
    const std::string text = effective.substr(at + 14, effective.find('&', at) - (at + 14));
    char* end = nullptr;
    errno = 0;
    const long want = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || want <= 0)
      throw std::runtime_error("LCM URL '" + effective + "': recv_buf_size must be a positive integer [bytes], got '" + text + "'");
    const long got = granted_receive_buffer(want);
    if (got < want)
      throw std::runtime_error("LCM URL '" + effective + "' asks for a " + std::to_string(want) +
                               "-byte receive buffer, the kernel grants " + std::to_string(got) +
                               " (net.core.rmem_max): raise it (sysctl -w net.core.rmem_max=" + std::to_string(want) +
                               ") or ask for less");
  }
  lcm_ = std::make_unique<lcm::LCM>(url);
  if (!lcm_->good())
    throw std::runtime_error("cannot initialise LCM (url '" + url +
                             "'): is there a multicast route? see docs/processes-and-protocol.md, 'Networking'");
}

void LcmBus::publish_raw(const std::string& channel, const void* data, int size) {
  int err = 0;
  for (int attempt = 0; attempt < kPublishAttempts; ++attempt) {
    errno = 0;
    if (lcm_->publish(channel, data, static_cast<unsigned int>(size)) == 0) {
      published_[channel].insert(std::hash<std::string_view>{}(std::string_view(static_cast<const char*>(data),
                                                                               static_cast<std::size_t>(size))));
      if (record_) record(channel, data, size);
      return;
    }
    err = errno;
    std::this_thread::sleep_for(std::chrono::milliseconds(1 << attempt));
  }
  throw std::runtime_error("LCM publish failed on channel " + channel + " (" + std::to_string(size) + " bytes) " +
                           std::to_string(kPublishAttempts) + " times: " + (err ? std::strerror(err) : "no reason given"));
}

std::map<std::string, long> LcmBus::published_counts() const {
  std::map<std::string, long> n;
  for (const auto& [channel, digests] : published_) n[channel] = static_cast<long>(digests.size());
  return n;
}

void LcmBus::record_publishes(const std::string& file) {
  record_ = std::make_unique<lcm::LogFile>(file, "w");
  if (!record_->good()) throw std::runtime_error("cannot create the record file " + file);
  record_file_ = file;
}

void LcmBus::record(const std::string& channel, const void* data, int size) {
  lcm::LogEvent e;
  e.eventnum = record_events_++;
  e.timestamp = std::chrono::duration_cast<std::chrono::microseconds>(
                    std::chrono::system_clock::now().time_since_epoch()).count();
  e.channel = channel;
  e.datalen = size;
  e.data = const_cast<void*>(data);
  if (record_->writeEvent(&e) != 0) throw std::runtime_error("cannot write to the record file " + record_file_);
}

void LcmBus::finish_record() {
  if (!record_) return;
  const bool ok = std::fflush(record_->getFilePtr()) == 0 && std::ferror(record_->getFilePtr()) == 0;
  record_.reset();
  if (!ok) throw std::runtime_error("cannot write to the record file " + record_file_);
}

void LcmBus::dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Sub* sub) {
  // Exceptions must not unwind through LCM's C code: keep the first, rethrow from handle().
  if (sub->bus->pending_) return;
  try {
    sub->handler(channel, rbuf->data, static_cast<int>(rbuf->data_size));
  } catch (...) {
    sub->bus->pending_ = std::current_exception();
  }
}

void LcmBus::subscribe_raw(const std::string& channel, RawHandler handler) {
  subs_.push_back(Sub{this, std::move(handler)});
  lcm::Subscription* sub = lcm_->subscribeFunction<Sub*>(channel, &LcmBus::dispatch, &subs_.back());
  // LCM's default queue of 30 messages drops bursts; a window's batches are far fewer than this.
  sub->setQueueCapacity(100000);
}

bool LcmBus::handle(int timeout_ms) {
  errno = 0;
  const int r = lcm_->handleTimeout(timeout_ms);
  if (r < 0 && errno == EINTR) return false;  // a signal (e.g. SIGTERM to a free-running node)
  if (r < 0) throw std::runtime_error("LCM handle failed");
  if (pending_) std::rethrow_exception(std::exchange(pending_, nullptr));
  return r > 0;
}

}  // namespace rnav
