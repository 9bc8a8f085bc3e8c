#include "estimators/diagnosis/io/lcm_event_reader.hpp"

#include "common/io/config.hpp"

#include <filesystem>

namespace rnav {

namespace {

std::uint64_t be(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

LcmEventReader::LcmEventReader(const std::string& file)
    : file_((require_regular_file(file), file)), in_(file, std::ios::binary) {
  std::error_code ec;
  size_ = static_cast<std::int64_t>(std::filesystem::file_size(file, ec));
  if (!in_ || ec) throw ConfigError(file + ": cannot open for reading");
}

bool LcmEventReader::next(LcmEvent& e) {
  constexpr int kHeaderBytes = 4 + 8 + 8 + 4 + 4;
  if (offset_ == size_) return false;
  const std::string at = file_ + ": event " + std::to_string(ordinal_) + " (byte " + std::to_string(offset_) + ")";
  if (size_ - offset_ < kHeaderBytes)
    throw ConfigError(at + ": the file ends inside an event header (" + std::to_string(size_ - offset_) +
                      " bytes left): the log was cut");
  std::uint8_t h[kHeaderBytes];
  in_.read(reinterpret_cast<char*>(h), kHeaderBytes);
  if (!in_) throw ConfigError(at + ": read error");
  if (be(h, 4) != kSyncWord) throw ConfigError(at + ": no sync word 0xEDA1DA01 (corrupt or not an LCM log)");
  const auto eventnum = static_cast<std::int64_t>(be(h + 4, 8));
  const auto timestamp = static_cast<std::int64_t>(be(h + 12, 8));
  const auto chan_len = static_cast<std::int32_t>(be(h + 20, 4));
  const auto data_len = static_cast<std::int32_t>(be(h + 24, 4));
  if (chan_len <= 0 || chan_len > kMaxChannelBytes)
    throw ConfigError(at + ": channel name length " + std::to_string(chan_len) + " outside [1, " +
                      std::to_string(kMaxChannelBytes) + "] (corrupt)");
  if (data_len < 0 || data_len > kMaxDataBytes)
    throw ConfigError(at + ": data length " + std::to_string(data_len) + " outside [0, " + std::to_string(kMaxDataBytes) +
                      "] (corrupt)");
  const std::int64_t need = kHeaderBytes + static_cast<std::int64_t>(chan_len) + data_len;
  if (size_ - offset_ < need)
    throw ConfigError(at + ": claims " + std::to_string(need) + " bytes, the file has " +
                      std::to_string(size_ - offset_) + " left: the log was cut or the sizes are corrupt");
  if (eventnum <= last_eventnum_)
    throw ConfigError(at + ": event number " + std::to_string(eventnum) + " after " + std::to_string(last_eventnum_) +
                      " (they must increase; corrupt or spliced)");
  e.eventnum = eventnum;
  e.timestamp_us = timestamp;
  e.offset = offset_;
  e.channel.resize(static_cast<std::size_t>(chan_len));
  in_.read(e.channel.data(), chan_len);
  e.data.resize(static_cast<std::size_t>(data_len));
  in_.read(reinterpret_cast<char*>(e.data.data()), data_len);
  if (!in_) throw ConfigError(at + ": read error");
  last_eventnum_ = eventnum;
  offset_ += need;
  ++ordinal_;
  return true;
}

}  // namespace rnav
