#include "lcm_bus.hpp"

#include <stdexcept>
#include <utility>

namespace rnav {

LcmBus::LcmBus(const std::string& url) : lcm_(std::make_unique<lcm::LCM>(url)) {
  if (!lcm_->good())
    throw std::runtime_error("cannot initialise LCM (url '" + url +
                             "'): is there a multicast route? see README, 'Networking'");
}

void LcmBus::publish_raw(const std::string& channel, const void* data, int size) {
  if (lcm_->publish(channel, data, static_cast<unsigned int>(size)) != 0)
    throw std::runtime_error("LCM publish failed on channel " + channel);
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
  const int r = lcm_->handleTimeout(timeout_ms);
  if (r < 0) throw std::runtime_error("LCM handle failed");
  if (pending_) std::rethrow_exception(std::exchange(pending_, nullptr));
  return r > 0;
}

}  // namespace rnav
