// Message bus: the only way nodes talk. Two transports share this interface:
// LcmBus (separate processes over LCM) and InprocBus (all nodes in one process, for the
// single-process ensemble and tests). Messages always travel LCM-encoded, so both transports
// exercise the same encode/decode path and give byte-identical results.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace rnav {

class Bus {
 public:
  using RawHandler = std::function<void(const std::string& channel, const void* data, int size)>;
  virtual ~Bus() = default;

  virtual void publish_raw(const std::string& channel, const void* data, int size) = 0;
  virtual void subscribe_raw(const std::string& channel, RawHandler handler) = 0;

  /// The run this process belongs to: every lock-step message carries it, and a message of
  /// another run on the same network is ignored and counted. LcmBus takes it from the
  /// environment (RNAV_RUN_ID, drawn by scripts/run; 0 when unset, so processes started by hand
  /// agree); one process's buses (InprocBus) use 0.
  std::int64_t run_id() const { return run_id_; }
  void set_run_id(std::int64_t id) { run_id_ = id; }

  template <class T> void publish(const std::string& channel, const T& msg) {
    const int n = msg.getEncodedSize();
    buf_.resize(static_cast<std::size_t>(n));
    if (msg.encode(buf_.data(), 0, n) != n)
      throw std::runtime_error("cannot encode message for channel " + channel);
    publish_raw(channel, buf_.data(), n);
  }

  template <class T> void subscribe(const std::string& channel, std::function<void(const T&)> h) {
    subscribe_raw(channel, [h](const std::string& ch, const void* data, int size) {
      T msg;
      if (msg.decode(data, 0, size) != size)
        throw std::runtime_error("cannot decode a message on channel " + ch +
                                 " (wrong type or corrupt)");
      h(msg);
    });
  }

 private:
  std::vector<std::uint8_t> buf_;
  std::int64_t run_id_ = 0;
};

/// All subscribers in one process: publish() queues, run_until_idle() delivers in FIFO order.
class InprocBus : public Bus {
 public:
  /// Optional tap: called with every message at publish time, in publish order, before it is
  /// queued (e.g. to record an LCM event log of an in-process run). Must not publish.
  RawHandler on_publish;

  void publish_raw(const std::string& channel, const void* data, int size) override {
    if (on_publish) on_publish(channel, data, size);
    const auto* p = static_cast<const std::uint8_t*>(data);
    queue_.push_back({channel, std::vector<std::uint8_t>(p, p + size)});
  }
  void subscribe_raw(const std::string& channel, RawHandler handler) override {
    handlers_[channel].push_back(std::move(handler));
  }
  /// Deliver queued messages (and those they cause) until none is left.
  void run_until_idle() {
    while (!queue_.empty()) {
      const Item item = std::move(queue_.front());
      queue_.pop_front();
      auto it = handlers_.find(item.channel);
      if (it == handlers_.end()) continue;
      for (auto& h : it->second)
        h(item.channel, item.data.data(), static_cast<int>(item.data.size()));
    }
  }

 private:
  struct Item {
    std::string channel;
    std::vector<std::uint8_t> data;
  };
  std::deque<Item> queue_;
  std::map<std::string, std::vector<RawHandler>> handlers_;
};

}  // namespace rnav
