#include "estimators/diagnosis/io/lcm_log_streams.hpp"

#include "common/node/channels.hpp"
#include "estimators/diagnosis/io/lcm_event_reader.hpp"
#include "common/node/lockstep_node.hpp"


#include <filesystem>
#include <fstream>
#include <sstream>

namespace rnav {

bool is_lcm_log(const std::string& file) {
  if (!std::filesystem::is_regular_file(file)) return false;
  std::ifstream f(file, std::ios::binary);
  unsigned char b[4] = {0, 0, 0, 0};
  f.read(reinterpret_cast<char*>(b), 4);
  return f.gcount() == 4 && b[0] == 0xED && b[1] == 0xA1 && b[2] == 0xDA && b[3] == 0x01;
}

namespace {

// "0-4, 7" from a set of integers.
std::string ranges(const std::set<int>& v) {
  std::string out;
  for (auto it = v.begin(); it != v.end();) {
    int a = *it, b = a;
    ++it;
    while (it != v.end() && *it == b + 1) b = *it++;
    out += (out.empty() ? "" : ", ") + std::to_string(a) + (b > a ? "-" + std::to_string(b) : "");
  }
  return out;
}

std::string span(std::int64_t b, std::int64_t e) {
  return "[" + std::to_string(b) + ", " + std::to_string(e) + ") us";
}

}  // namespace

LcmLogStreams::Stream* LcmLogStreams::find(const std::string& channel) {
  for (auto& s : streams_)
    if (s->channel == channel) return s.get();
  return nullptr;
}

const LcmLogStreams::Stream& LcmLogStreams::stream(const std::string& channel) const {
  for (const auto& s : streams_)
    if (s->channel == channel) return *s;
  throw std::logic_error("LcmLogStreams: no stream " + channel + " declared");
}

std::string LcmLogStreams::where(const std::string& channel) const {
  return file_ + ": " + channel + ", realization " + std::to_string(realization_) + ", attempt " +
         std::to_string(attempt_);
}

const sim_scenario_t* LcmLogStreams::scenario() const {
  auto it = scenarios_.upper_bound(attempt_);
  if (it == scenarios_.begin()) return nullptr;
  return &std::prev(it)->second;
}

void LcmLogStreams::read(const std::string& file, int realization, const std::string& kind) {
  file_ = file;
  realization_ = realization;
  if (!std::filesystem::exists(file)) throw ConfigError(file + ": no such file");
  if (!is_lcm_log(file))
    throw ConfigError(file + ": not an LCM event log (it does not start with the sync word 0xEDA1DA01)");
  LcmEventReader log(file);  // bounded: every size checked against the file before it is read

  std::map<int, std::set<int>> attempts;  // realization -> attempts seen (grants and batches)
  std::vector<Grant> grants;               // START grants of `realization`, every attempt
  std::size_t moved_on_index = 0;          // last position of a later START or FINISH (+1)
  std::string abort_reason;
  std::set<std::string> channels;
  std::map<std::int64_t, long> runs;       // run id -> grants and batches carrying it
  std::size_t index = 0;
  LcmEvent event;
  while (log.next(event)) {
    const LcmEvent* e = &event;
    const int datalen = static_cast<int>(e->data.size());
    ++index;
    ++n_events_;
    channels.insert(e->channel);
    auto undecodable = [&](const std::string& type) {
      return ConfigError(file + ": event " + std::to_string(e->eventnum) + " on channel " + e->channel +
                         " does not decode as rnav::" + type +
                         " (wrong type or corrupt; a run with runner.wire=sample, as scripts/run --realtime makes, "
                         "logs one message per sample, which this reader does not take: record a run without --realtime)");
    };
    if (e->channel == ch::kWindow) {
      sim_window_t w;
      if (w.decode(e->data.data(), 0, datalen) != datalen) throw undecodable("sim_window_t");
      // A RESEND repeats its window's grant (a node that lost the START takes it as the START),
      // so it stands for a START the log lost; repeated grants of one window count once.
      if (w.command == sim_window_t::START || w.command == sim_window_t::RESEND) {
        ++runs[w.run_id];
        attempts[w.realization].insert(w.attempt);
        if (w.realization == realization) {
          bool seen = false;
          for (const auto& g : grants) seen = seen || (g.w.attempt == w.attempt && g.w.window == w.window);
          if (!seen) grants.push_back({e->eventnum, index, w});
        } else if (w.realization > realization) {
          moved_on_index = index;
        }
      } else if (w.command == sim_window_t::FINISH) {
        moved_on_index = index;
      } else if (w.command == sim_window_t::ABORT) {
        abort_reason = w.reason;
      }
    } else if (e->channel == ch::kScenario) {
      sim_scenario_t s;
      if (s.decode(e->data.data(), 0, datalen) != datalen) throw undecodable("sim_scenario_t");
      if (s.realization == realization) scenarios_[s.attempt] = s;
    } else if (Stream* s = find(e->channel)) {
      Item it;
      it.event = e->eventnum;
      it.digest = message_digest(e->data.data(), datalen);
      if (!s->decode(e->data.data(), datalen, it.h, it.msg)) throw undecodable("batch of " + s->channel);
      ++runs[it.h.run_id];
      attempts[it.h.realization].insert(it.h.attempt);
      if (it.h.realization == realization) s->items.push_back(std::move(it));
      else ++n_other_realizations_;
    } else {
      ++ignored_[e->channel];
    }
  }

  // Two runs on one network (another user's under --net host, or a log replayed during the
  // recording) put two sets of realizations, attempts and windows in one log: mixed, their
  // streams would fail the checks below with a confusing gap or duplicate, or worse pass.
  if (runs.size() > 1) {
    std::string list;
    for (const auto& [id, k] : runs)
      list += (list.empty() ? "" : ", ") + std::to_string(id) + " (" + std::to_string(k) + " grants and batches)";
    throw ConfigError(file + ": the log holds the traffic of " + std::to_string(runs.size()) + " runs (run ids " + list +
                      "): a log must hold one run; record each run on its own network (scripts/run's default "
                      "private namespace) or its own --lcm-url");
  }
  if (!attempts.count(realization)) {
    std::set<int> present;
    for (const auto& [r, a] : attempts) present.insert(r);
    std::string list;
    for (const auto& c : channels) list += (list.empty() ? "" : ", ") + c;
    throw ConfigError(file + ": realization " + std::to_string(realization) + " is not in the log; " +
                      (present.empty() ? "it holds no simulation batches or grants (channels: " +
                                             (list.empty() ? std::string("none") : list) + ")"
                                       : "realizations present: " + ranges(present)));
  }
  attempt_ = *attempts[realization].rbegin();
  if (const sim_scenario_t* sc = scenario(); sc && !kind.empty() && sc->kind != kind)
    throw ConfigError(file + ": the log holds a '" + sc->kind + "' run (SIM_SCENARIO), not a '" + kind +
                      "' one: use diagnose " + sc->kind);
  for (const auto& g : grants)
    if (g.w.attempt == attempt_) grants_.push_back(g);
  check_grants(moved_on_index, abort_reason);
  for (auto& s : streams_) {
    for (const auto& it : s->items) n_earlier_ += it.h.attempt < attempt_;
    check_stream(*s);
  }
}

void LcmLogStreams::check_grants(std::size_t moved_on_index, const std::string& abort_reason) {
  const std::string w = where(ch::kWindow);
  if (grants_.empty())
    throw ConfigError(w + ": no window grant in the log, so it cannot tell whether the attempt "
                          "completed (record every channel, including SIM_WINDOW)");
  for (std::size_t i = 0; i < grants_.size(); ++i) {
    const Grant& g = grants_[i];
    if (g.w.window != static_cast<int>(i))
      throw ConfigError(w + ": grant of window " + std::to_string(g.w.window) + " at event " +
                        std::to_string(g.event) + ", expected window " + std::to_string(i) +
                        (g.w.window > static_cast<int>(i) ? " (a grant is missing)" : " (duplicate or out of order)"));
    if (g.w.last_window && i + 1 < grants_.size())
      throw ConfigError(w + ": grant of window " + std::to_string(grants_[i + 1].w.window) + " at event " +
                        std::to_string(grants_[i + 1].event) + " after the last window " +
                        std::to_string(g.w.window));
  }
  const std::string incomplete = file_ + ": realization " + std::to_string(realization_) + " attempt " +
                                 std::to_string(attempt_) + " (the last one in the log) did not complete: ";
  const std::string why = abort_reason.empty() ? "" : " (the run aborted: " + abort_reason + ")";
  if (!grants_.back().w.last_window)
    throw ConfigError(incomplete + "its last grant is window " + std::to_string(grants_.back().w.window) +
                      " at event " + std::to_string(grants_.back().event) +
                      ", not the realization's last window; the run failed or the log was cut" + why);
  if (moved_on_index <= grants_.back().index)
    throw ConfigError(incomplete + "the clock never moved past it (no later realization or FINISH "
                      "on SIM_WINDOW after its last window); the run failed, the realization was "
                      "repeated after the log ended, or the log was cut" + why);
}

void LcmLogStreams::check_stream(Stream& s) {
  const std::string w = where(s.channel);
  const std::size_t n = grants_.size();
  for (const Item& it : s.items) {
    if (it.h.attempt != attempt_) continue;
    const std::size_t i = s.used.size();
    const std::string at = "window " + std::to_string(it.h.window) + " (event " + std::to_string(it.event) + ")";
    if (it.h.window < 0) throw ConfigError(w + ": " + at + ": a negative window index (corrupt)");
    // A copy of an earlier window - also of the last one, after it - is a resend (byte-identical).
    if (it.h.window < static_cast<int>(i)) {
      const Item& first = *s.used[static_cast<std::size_t>(it.h.window)];
      if (it.h.seq == first.h.seq && it.digest == first.digest) {
        ++n_resent_;  // published again on a consumer's WAITING: byte-identical, ignored
        continue;
      }
      throw ConfigError(w + ": " + at + " is a duplicate or out of order (expected window " +
                        std::to_string(i) + "; it differs from the batch of event " + std::to_string(first.event) + ")");
    }
    if (i >= n)
      throw ConfigError(w + ": " + at + " after the attempt's last window " + std::to_string(n - 1) +
                        " (duplicate or out of order)");
    if (it.h.window > static_cast<int>(i)) {
      for (const Item& later : s.items)
        if (&later > &it && later.h.attempt == attempt_ && later.h.window == static_cast<int>(i))
          throw ConfigError(w + ": window " + std::to_string(i) + " is out of order (event " +
                            std::to_string(later.event) + ", after " + at + ")");
      throw ConfigError(w + ": window " + std::to_string(i) + " is missing (lost; the next batch is " + at + ")");
    }
    if (i > 0 && it.h.seq != s.used[0]->h.seq + static_cast<std::int64_t>(i))
      throw ConfigError(w + ": " + at + " has seq " + std::to_string(it.h.seq) + ", expected " +
                        std::to_string(s.used[0]->h.seq + static_cast<std::int64_t>(i)) +
                        " (the publisher lost or repeated a message)");
    const sim_window_t& g = grants_[i].w;
    if (it.h.utime_begin != g.utime_begin || it.h.utime_end != g.utime_end)
      throw ConfigError(w + ": " + at + " spans " + span(it.h.utime_begin, it.h.utime_end) +
                        " but its grant spans " + span(g.utime_begin, g.utime_end));
    s.used.push_back(&it);
  }
  if (s.used.size() < n)
    throw ConfigError(w + ": window " + std::to_string(s.used.size()) + " is missing (lost; " +
                      (s.used.empty() ? std::string("the log has no batch of this attempt on this channel")
                                      : "the stream ends after window " + std::to_string(s.used.size() - 1)) +
                      ", the attempt has " + std::to_string(n) + " windows)");
}

std::string LcmLogStreams::summary() const {
  std::ostringstream os;
  os << file_ << ": " << n_events_ << " events; realization " << realization_ << " attempt " << attempt_
     << ", " << grants_.size() << " windows;";
  for (const auto& s : streams_) os << " " << s->channel << " " << s->used.size() << " batches;";
  os << " ignored: " << n_earlier_ << " batches of earlier attempts, " << n_resent_ << " resent copies, "
     << n_other_realizations_ << " of other realizations";
  long other = 0;
  for (const auto& [c, k] : ignored_) other += k;
  os << ", " << other << " events on other channels";
  if (!ignored_.empty()) {
    os << " (";
    bool first = true;
    for (const auto& [c, k] : ignored_) {
      os << (first ? "" : ", ") << c << " " << k;
      first = false;
    }
    os << ")";
  }
  return os.str();
}

}  // namespace rnav
