#include "scripts/compose/merge/shard_merge.hpp"

#include "common/io/atomic_file.hpp"
#include "common/io/config.hpp"
#include "common/io/csv_columns.hpp"
#include "sim/datalink/datalink_node.hpp"
#include "loggers/prl_stats.hpp"
#include "loggers/realization_set.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"
#include "loggers/uav_realizations.hpp"
#include "loggers/uav_stats.hpp"
#include "loggers/uav_track.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace rnav {

namespace {

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot be read (is it a shard's output folder?)");
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) throw std::runtime_error(path + ": read error");
  return s.str();
}

struct Shard {
  std::string dir;
  nlohmann::json state;
  std::string scenario_text;  // its scenario.json
  std::set<long> held;  // its realizations
  long first = -1;      // its lowest realization (-1: none)
};

// The merged realizations must be 0 ... n-1 (merge_state checked that no two shards share
// one): no gap may pass for a smaller ensemble. Names the missing ranges.
void check_complete(const std::set<long>& all) {
  if (all.empty()) throw std::invalid_argument("the shards hold no realization");
  const long top = *all.rbegin();
  if (static_cast<long>(all.size()) == top + 1) return;
  std::string gaps;
  long next = 0;
  for (long r : all) {
    if (r > next) gaps += (gaps.empty() ? "" : ", ") + std::to_string(next) + (r - 1 == next ? "" : " ... " + std::to_string(r - 1));
    next = r + 1;
  }
  throw std::invalid_argument("the shards hold " + std::to_string(all.size()) + " realizations, not realizations 0 ... " +
                              std::to_string(top) + " each once: missing " + gaps);
}

// The body of a CSV file (after its header line), whose header must be `header`.
std::string body_of(const std::string& path, const std::string& text, const std::string& header) {
  const auto nl = text.find('\n');
  if (nl == std::string::npos) throw std::runtime_error(path + ": no header line");
  if (text.compare(0, nl + 1, header) != 0)
    throw std::runtime_error(path + ": its header is not the one this build writes (" + header.substr(0, header.size() - 1) + ")");
  return text.substr(nl + 1);
}

// out_dir/name: the header of `columns`, then each shard's rows in the shards' order; and the
// columns' description beside it (NAME.units.json, as one run writes it).
void join_rows(const std::vector<Shard>& shards, const std::string& name, const std::vector<CsvColumnDoc>& columns,
               const std::string& out_dir) {
  const std::string header = csv_header(columns);
  AtomicFileWriter rows(out_dir, name);
  rows.append(header);
  for (const auto& s : shards) {
    const std::string path = s.dir + "/" + name;
    rows.append(body_of(path, read_text(path), header));
  }
  rows.commit();
  write_csv_units(out_dir, name, columns);
}

}  // namespace

MergeResult merge_shards(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  if (shard_dirs.empty()) throw std::invalid_argument("no shard to merge");
  std::string model_text;  // the first shard's scenario without its runner section
  std::vector<Shard> shards;
  MergeResult res;
  for (const auto& dir : shard_dirs) {
    const std::string sc_path = dir + "/scenario.json", st_path = dir + "/ensemble_state.json";
    const std::string sc = read_text(sc_path);
    // The runner section (lock-step window, wire, timeouts) does not change a result: shards run
    // in one process and over LCM (whose window scripts/run chooses) join. Everything else must match.
    nlohmann::json model = parse_json_checked(sc, sc_path, /*allow_comments=*/false);
    if (model.is_object()) model.erase("runner");
    const std::string m = model.dump();
    if (model_text.empty()) model_text = m;
    else if (m != model_text)
      throw std::invalid_argument(sc_path + " differs from " + shard_dirs.front() +
                                  "/scenario.json: shards of one ensemble run the same scenario");
    // Depth-limited, duplicate keys refused (the scenario files' parser): a state file is input.
    Shard s{dir, parse_json_checked(read_text(st_path), st_path, /*allow_comments=*/false), sc, {}, -1};
    if (!s.state.is_object() || !s.state.contains("kind") || !s.state.contains("seed") ||
        !s.state["seed"].is_number_integer())
      throw std::invalid_argument(st_path + ": not an ensemble state (JSON with kind and seed)");
    const std::string kind = s.state["kind"].is_string() ? s.state["kind"].get<std::string>() : "";
    if (res.kind.empty()) {
      res.kind = kind;
      res.seed = s.state["seed"].get<std::int64_t>();
    } else if (kind != res.kind) {
      throw std::invalid_argument(st_path + ": kind '" + kind + "', the first shard's is '" + res.kind + "'");
    }
    shards.push_back(std::move(s));
  }
  const std::string sc_file = shard_dirs.front() + "/scenario.json";
  // The statistics: each shard's exact state merged (any order), then written once.
  std::set<long> all;
  long track_realization = -1;
  std::filesystem::create_directories(out_dir);
  const auto merge_all = [&](auto& st) {
    for (auto& s : shards) {
      try {
        st.merge_state(s.state, res.seed, s.dir + "/ensemble_state.json");
      } catch (const nlohmann::json::exception& e) {  // a value of the wrong type
        throw std::invalid_argument(s.dir + "/ensemble_state.json: " + e.what());
      }
      s.held = realization_set(s.state["held"], s.dir + "/ensemble_state.json");
      s.first = s.held.empty() ? -1 : *s.held.begin();
    }
    all = st.realization_set();
    res.realizations = st.realizations();
    check_complete(all);
    // realizations.csv: each shard's rows are in its realization order; shards go in theirs, so
    // they must be ranges that do not interleave.
    std::sort(shards.begin(), shards.end(), [](const Shard& a, const Shard& b) { return a.first < b.first; });
    for (std::size_t i = 1; i < shards.size(); ++i)
      if (!shards[i - 1].held.empty() && *shards[i - 1].held.rbegin() > shards[i].first)
        throw std::invalid_argument(shards[i - 1].dir + " and " + shards[i].dir +
                                    ": shards must be realization ranges that do not interleave");
    st.write_statistics(out_dir, res.seed);
  };
  std::vector<CsvColumnDoc> row_columns;  // realizations.csv's, as one run of the kind writes them
  if (res.kind == "landing") {
    const Scenario sc = Scenario::load(sc_file, {});
    PrlStats st(sc.logger, sc.site());
    merge_all(st);
    row_columns = st.realizations_columns();
  } else if (res.kind == "uav") {
    const UavScenario sc = UavScenario::load(sc_file, {});
    UavStats st(sc.stats_setup());
    merge_all(st);
    track_realization = sc.logger.track_realization;
    row_columns = uav_realizations_columns();
  } else {
    throw std::invalid_argument(shard_dirs.front() + "/ensemble_state.json: unknown kind '" + res.kind + "'");
  }
  join_rows(shards, "realizations.csv", row_columns, out_dir);
  // datalink.csv (a landing run with datalink.enabled): per realization, joined the same way.
  // The shards ran one scenario (checked above), so either all have one or none.
  if (std::filesystem::exists(shards.front().dir + "/datalink.csv"))
    join_rows(shards, "datalink.csv", DatalinkNode::csv_columns(), out_dir);
  // track.csv (azimuth-only): from the shard that ran logger.track_realization, with the
  // description of its columns (which depend on the estimators it holds).
  if (track_realization >= 0) {
    if (track_realization >= res.realizations)
      throw std::invalid_argument("logger.track_realization " + std::to_string(track_realization) +
                                  " names no realization of the merged ensemble (0 ... " + std::to_string(res.realizations - 1) + ")");
    for (const auto& s : shards)
      if (s.held.count(track_realization)) {
        const std::string path = s.dir + "/track.csv", text = read_text(path);
        const auto columns = UavTrack::columns_of_header(text, path);
        write_file_atomic(out_dir, "track.csv", text);
        write_csv_units(out_dir, "track.csv", columns);
      }
  }
  // The scenario as the shard holding realization 0 ran it (whatever order the shards came in).
  write_file_atomic(out_dir, "scenario.json", shards.front().scenario_text);
  return res;
}

}  // namespace rnav
