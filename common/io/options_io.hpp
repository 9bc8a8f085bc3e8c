// Reading and printing option structs from one description of their keys.
//
// Each options struct has a `visit(Options&, V&)` listing its keys with unit-bearing names and
// ranges; Reader parses a scenario Section through it (strictly: unknown keys, wrong types,
// NaN, out-of-range values are ConfigErrors naming the key) and Writer dumps it for the
// start-up print. One list, so parsing and printing cannot disagree.
#pragma once

#include "common/io/config.hpp"
#include "common/io/did_you_mean.hpp"
#include "common/physics/sim_time.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace rnav::options_io {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One description of every key, used both to parse (Reader) and to print (Writer).
struct Reader {
  Section& s;
  void num(const char* k, double& x, double lo, double hi) { x = s.number(k, x, lo, hi); }
  void integer(const char* k, long& x, long lo, long hi) { x = s.integer(k, x, lo, hi); }
  void i64(const char* k, std::int64_t& x, double lo, double hi) {
    x = static_cast<std::int64_t>(s.number(k, static_cast<double>(x), lo, hi));
  }
  void flag(const char* k, bool& x) { x = s.boolean(k, x); }
  /// Any string (e.g. a file path; "" allowed).
  void str(const char* k, std::string& x) { x = s.string(k, x); }
  void choice(const char* k, std::string& x, const std::vector<std::string>& allowed) {
    x = s.string(k, x);
    for (const auto& a : allowed)
      if (a == x) return;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw ConfigError("scenario key '" + s.key_path(k) + "': '" + x + "' is not one of " + list +
                      did_you_mean(x, allowed));
  }
  /// A non-empty list of distinct names, each one of `allowed` (did-you-mean for a misspelt one).
  void choices(const char* k, std::vector<std::string>& x, const std::vector<std::string>& allowed) {
    x = s.strings(k, x);
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    if (x.empty()) throw ConfigError("scenario key '" + s.key_path(k) + "': the list is empty; give one or more of " + list);
    for (std::size_t i = 0; i < x.size(); ++i) {
      bool known = false;
      for (const auto& a : allowed) known = known || a == x[i];
      if (!known)
        throw ConfigError("scenario key '" + s.key_path(k) + "': '" + x[i] + "' is not one of " + list +
                          did_you_mean(x[i], allowed));
      for (std::size_t j = 0; j < i; ++j)
        if (x[j] == x[i]) throw ConfigError("scenario key '" + s.key_path(k) + "': '" + x[i] + "' is listed twice");
    }
  }
  void list(const char* k, std::vector<double>& x, double lo, double hi) {
    x = s.numbers(k, x, lo, hi);
  }
  void intervals(const char* k, std::vector<std::pair<double, double>>& x, double lo, double hi) {
    if (s.has(k)) x = s.intervals(k, lo, hi); else (void)s.intervals(k, lo, hi);
  }
  /// A list of 4-number rows (e.g. manoeuvres); every number finite.
  void quads(const char* k, std::vector<std::array<double, 4>>& x) {
    if (!s.has(k)) { (void)s.numbers(k, {}, 0, 0); return; }
    x = s.rows4(k);
  }
};

struct Writer {
  nlohmann::json& j;
  void num(const char* k, double& x, double, double) { j[k] = x; }
  void integer(const char* k, long& x, long, long) { j[k] = x; }
  void i64(const char* k, std::int64_t& x, double, double) { j[k] = x; }
  void flag(const char* k, bool& x) { j[k] = x; }
  void str(const char* k, std::string& x) { j[k] = x; }
  void choice(const char* k, std::string& x, const std::vector<std::string>&) { j[k] = x; }
  void choices(const char* k, std::vector<std::string>& x, const std::vector<std::string>&) { j[k] = x; }
  void list(const char* k, std::vector<double>& x, double, double) { j[k] = x; }
  void intervals(const char* k, std::vector<std::pair<double, double>>& x, double, double) {
    j[k] = nlohmann::json::array();
    for (auto& p : x) j[k].push_back({p.first, p.second});
  }
  void quads(const char* k, std::vector<std::array<double, 4>>& x) {
    j[k] = nlohmann::json::array();
    for (auto& p : x) j[k].push_back(p);
  }
};

template <class O> void read_section(Section& root, const char* name, O& o) {
  Section s = root.section(name);
  Reader r{s};
  visit(o, r);
  s.finish();
}
template <class O> void write_section(nlohmann::json& root, const char* name, O& o) {
  Writer w{root[name]};
  visit(o, w);
}

// What for_each_section(sc, f) calls f with, for every section of a scenario type.
struct SectionReader {
  Section& root;
  template <class O> void operator()(const char* name, O& o) const { read_section(root, name, o); }
};
struct SectionWriter {
  nlohmann::json& root;
  template <class O> void operator()(const char* name, O& o) const { write_section(root, name, o); }
};

/// Parse the document `doc` of a scenario of kind `kind` into `sc` (its defaults set): "name",
/// "kind" (`kind` when absent, else must be it), `read_top(root)` for the keys outside the
/// sections, then every section of sc in for_each_section(Sc&, F&&) (found by ADL through
/// SectionReader); any key left unread is a ConfigError.
template <class Sc, class ReadTop>
void read_scenario(const nlohmann::json& doc, const std::string& kind, Sc& sc, ReadTop&& read_top) {
  Section root(doc, "");
  sc.name = root.string("name", sc.name);
  const std::string given = root.string("kind", kind);
  if (given != kind) throw ConfigError("scenario key 'kind': expected \"" + kind + "\", got \"" + given + "\"");
  read_top(root);
  for_each_section(sc, SectionReader{root});
  root.finish();
}

/// Print scenario `sc` as JSON (two-space indent, a newline after): "name", what
/// `write_top(j)` adds, then every section of sc.
template <class Sc, class WriteTop> void print_scenario(Sc sc, std::ostream& os, WriteTop&& write_top) {
  nlohmann::json j;
  j["name"] = sc.name;
  write_top(j);
  for_each_section(sc, SectionWriter{j});
  os << j.dump(2) << "\n";
}

// t must be an integer multiple of step (both in us).
inline void require_multiple(double t_s, double step_s, const std::string& key,
                             const std::string& step_key = "trajectory.step_s") {
  const auto t = to_us(t_s), step = to_us(step_s);
  if (step <= 0 || t % step != 0)
    throw ConfigError("scenario key '" + key + "' = " + std::to_string(t_s) +
                      " s must be a multiple of " + step_key + " = " + std::to_string(step_s) +
                      " s (all samples lie on the truth grid)");
}


/// Load a scenario file of type Sc (Sc::from_json) with "a.b=value" overrides applied first;
/// errors name the file.
template <class Sc>
Sc load_scenario(const std::string& file, const std::vector<std::string>& overrides) {
  nlohmann::json doc = load_json_file(file);
  for (const auto& o : overrides) apply_override(doc, o);
  try {
    return Sc::from_json(doc);
  } catch (const ConfigError& e) {
    throw ConfigError(file + ": " + e.what());
  }
}

}  // namespace rnav::options_io
