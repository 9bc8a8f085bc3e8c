// A reader of LCM event logs (the lcm-logger format) that trusts nothing in the file: LCM's own
// reader allocates whatever an event header claims (a flipped bit in a size field asks for
// gigabytes or reads past the end). Format, per event, big-endian: sync word 0xEDA1DA01, event
// number (int64), timestamp [us] (int64), channel length (int32), data length (int32), channel,
// data.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace rnav {

struct LcmEvent {
  std::int64_t eventnum = 0;
  std::int64_t timestamp_us = 0;  ///< [us] when the recorder received it
  std::string channel;
  std::vector<std::uint8_t> data;
  std::int64_t offset = 0;        ///< [bytes] of its sync word in the file
};

class LcmEventReader {
 public:
  static constexpr std::int32_t kMaxChannelBytes = 256;        ///< LCM's limit is 63; some slack
  static constexpr std::int32_t kMaxDataBytes = 256 << 20;     ///< 256 MiB: far above any batch
  static constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;

  /// Opens `file`; throws ConfigError naming it if it cannot be read.
  explicit LcmEventReader(const std::string& file);
  /// The next event into `e`; false at the clean end of the file. Throws ConfigError naming the
  /// file, the event's ordinal and byte offset for a bad sync word, a negative or oversized
  /// length, an event cut short by the end of the file, or event numbers that do not increase.
  bool next(LcmEvent& e);

 private:
  std::string file_;
  std::ifstream in_;
  std::int64_t offset_ = 0, ordinal_ = 0, last_eventnum_ = -1;
  std::int64_t size_ = 0;
};

}  // namespace rnav
