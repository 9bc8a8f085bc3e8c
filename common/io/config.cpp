#include "common/io/config.hpp"

#include "common/io/did_you_mean.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <cctype>
#include <set>
#include <sstream>

namespace rnav {

long long parse_integer(const std::string& option, const std::string& text, long long lo, long long hi) {
  std::size_t pos = 0;
  long long x = 0;
  bool ok = !text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '-');
  if (ok) {
    try {
      x = std::stoll(text, &pos);
    } catch (const std::out_of_range&) {
      // all digits, beyond long long: an integer, out of range (not "not an integer")
      const bool digits = text.find_first_not_of("0123456789", text[0] == '-' ? 1 : 0) == std::string::npos;
      if (digits && text.size() > (text[0] == '-' ? 1u : 0u))
        throw ConfigError(option + ": " + text + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      ok = false;
    } catch (const std::exception&) {
      ok = false;
    }
  }
  if (!ok || pos != text.size())
    throw ConfigError(option + ": '" + text + "' is not an integer");
  if (x < lo || x > hi)
    throw ConfigError(option + ": " + text + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return x;
}

std::string value_text(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

namespace {
std::string fmt(double v) { return value_text(v); }
}  // namespace

Section::Section(const nlohmann::json& j, std::string path) : j_(j), path_(std::move(path)) {
  if (j_.is_null()) j_ = nlohmann::json::object();
  if (!j_.is_object())
    throw ConfigError("scenario key '" + (path_.empty() ? std::string("<root>") : path_) +
                      "': expected an object, got " + j_.dump());
}

std::string Section::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool Section::has(const std::string& key) const { return j_.contains(key); }

const nlohmann::json* Section::find(const std::string& key) {
  used_.insert(key);
  auto it = j_.find(key);
  if (it == j_.end() || it->is_null()) return nullptr;
  return &*it;
}

double Section::as_number(const std::string& key, const nlohmann::json& v, double lo,
                          double hi) const {
  if (!v.is_number())
    throw ConfigError("scenario key '" + key_path(key) + "': expected a number, got " + v.dump());
  const double x = v.get<double>();
  if (!std::isfinite(x))
    throw ConfigError("scenario key '" + key_path(key) + "': not a finite number");
  if (x < lo || x > hi)
    throw ConfigError("scenario key '" + key_path(key) + "': " + fmt(x) + " is out of range [" +
                      fmt(lo) + ", " + fmt(hi) + "]");
  return x;
}

double Section::number(const std::string& key, double def, double lo, double hi) {
  const auto* v = find(key);
  return v ? as_number(key, *v, lo, hi) : def;
}

double Section::required_number(const std::string& key, double lo, double hi) {
  const auto* v = find(key);
  if (!v) throw ConfigError("scenario key '" + key_path(key) + "' is required");
  return as_number(key, *v, lo, hi);
}

long Section::integer(const std::string& key, long def, long lo, long hi) {
  const auto* v = find(key);
  if (!v) return def;
  if (!v->is_number_integer())
    throw ConfigError("scenario key '" + key_path(key) + "': expected an integer, got " +
                      v->dump());
  const long x = v->get<long>();
  if (x < lo || x > hi)
    throw ConfigError("scenario key '" + key_path(key) + "': " + std::to_string(x) +
                      " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return x;
}

bool Section::boolean(const std::string& key, bool def) {
  const auto* v = find(key);
  if (!v) return def;
  if (!v->is_boolean())
    throw ConfigError("scenario key '" + key_path(key) + "': expected true or false, got " +
                      v->dump());
  return v->get<bool>();
}

std::string Section::string(const std::string& key, const std::string& def) {
  const auto* v = find(key);
  if (!v) return def;
  if (!v->is_string())
    throw ConfigError("scenario key '" + key_path(key) + "': expected a string, got " + v->dump());
  return v->get<std::string>();
}

std::vector<std::pair<double, double>> Section::intervals(const std::string& key, double lo,
                                                          double hi) {
  std::vector<std::pair<double, double>> out;
  const auto* v = find(key);
  if (!v) return out;
  if (!v->is_array())
    throw ConfigError("scenario key '" + key_path(key) +
                      "': expected a list of [begin, end] pairs, got " + v->dump());
  for (const auto& p : *v) {
    if (!p.is_array() || p.size() != 2)
      throw ConfigError("scenario key '" + key_path(key) + "': expected [begin, end], got " +
                        p.dump());
    const double a = as_number(key, p[0], lo, hi), b = as_number(key, p[1], lo, hi);
    if (!(a < b))
      throw ConfigError("scenario key '" + key_path(key) + "': interval " + p.dump() +
                        " must have begin < end");
    out.emplace_back(a, b);
  }
  return out;
}

std::vector<double> Section::numbers(const std::string& key, const std::vector<double>& def,
                                     double lo, double hi) {
  const auto* v = find(key);
  if (!v) return def;
  if (!v->is_array())
    throw ConfigError("scenario key '" + key_path(key) + "': expected a list of numbers, got " +
                      v->dump());
  std::vector<double> out;
  for (const auto& x : *v) out.push_back(as_number(key, x, lo, hi));
  return out;
}

std::vector<std::string> Section::strings(const std::string& key, const std::vector<std::string>& def) {
  const auto* v = find(key);
  if (!v) return def;
  if (!v->is_array())
    throw ConfigError("scenario key '" + key_path(key) + "': expected a list of strings, got " + v->dump() +
                      " (a JSON list; on the command line: --set '" + key_path(key) + "=[\"a\",\"b\"]')");
  std::vector<std::string> out;
  for (const auto& x : *v) {
    if (!x.is_string())
      throw ConfigError("scenario key '" + key_path(key) + "': expected a list of strings, got " + x.dump() +
                        " in it");
    out.push_back(x.get<std::string>());
  }
  return out;
}

std::vector<std::array<double, 4>> Section::rows4(const std::string& key) {
  std::vector<std::array<double, 4>> out;
  const auto* v = find(key);
  if (!v) return out;
  if (!v->is_array())
    throw ConfigError("scenario key '" + key_path(key) + "': expected a list of 4-number rows, got " +
                      v->dump());
  for (const auto& r : *v) {
    if (!r.is_array() || r.size() != 4)
      throw ConfigError("scenario key '" + key_path(key) + "': expected 4 numbers, got " + r.dump());
    std::array<double, 4> row;
    for (int i = 0; i < 4; ++i) row[i] = as_number(key, r[i], -1e9, 1e9);
    out.push_back(row);
  }
  return out;
}

Section Section::section(const std::string& key) {
  const auto* v = find(key);
  Section s(v ? *v : nlohmann::json::object(), key_path(key));
  s.deferred_ = deferred_;
  s.nested_ = true;
  return s;
}

void Section::finish() const {
  std::vector<std::string> known;  // every key this section's reader asked for
  for (const auto& k : used_) known.push_back(key_path(k));
  std::vector<std::string> unknown;
  for (auto it = j_.begin(); it != j_.end(); ++it)
    if (!used_.count(it.key())) unknown.push_back(key_path(it.key()) + did_you_mean(key_path(it.key()), known));
  if (nested_) {  // named by the finish() of the section this one is nested in, with its own
    deferred_->insert(deferred_->end(), unknown.begin(), unknown.end());
    return;
  }
  unknown.insert(unknown.begin(), deferred_->begin(), deferred_->end());
  if (unknown.empty()) return;
  std::string list;
  for (const auto& u : unknown) list += (list.empty() ? "" : ", ") + u;
  throw ConfigError("unknown scenario key(s): " + list);
}

void Section::finish_nested() const {
  std::string list;
  for (const auto& u : *deferred_) list += (list.empty() ? "" : ", ") + u;
  if (!list.empty()) throw ConfigError("unknown scenario key(s): " + list);
}

namespace {
template <class Input>
nlohmann::json parse_checked(Input&& in, const std::string& source, bool allow_comments) {
  std::vector<std::set<std::string>> keys;  // of each object being parsed
  std::string last_key;                      // the key parsed last (named when a number overflows)
  const nlohmann::json::parser_callback_t check = [&](int depth, nlohmann::json::parse_event_t event,
                                                      nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if (depth > kMaxJsonDepth)
      throw ConfigError(source + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    if (event == E::object_start) keys.emplace_back();
    else if (event == E::object_end && !keys.empty()) keys.pop_back();
    else if (event == E::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
      throw ConfigError(source + ": key '" + parsed.get<std::string>() + "' appears twice in one object");
    if (event == E::key) last_key = parsed.get<std::string>();
    return true;
  };
  try {
    return nlohmann::json::parse(std::forward<Input>(in), check, true, allow_comments);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(source + ": " + e.what());
  } catch (const nlohmann::json::out_of_range& e) {
    // 1e400: nlohmann refuses it while parsing (out_of_range.406), before the callback sees it
    throw ConfigError(source + ": a number overflows the double range" +
                      (last_key.empty() ? std::string() : " (at or after key '" + last_key + "')") + ": " + e.what());
  }
}
}  // namespace

nlohmann::json parse_json_checked(std::istream& in, const std::string& source, bool allow_comments) {
  return parse_checked(in, source, allow_comments);
}

nlohmann::json parse_json_checked(const std::string& text, const std::string& source, bool allow_comments) {
  return parse_checked(text, source, allow_comments);
}

void require_regular_file(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::exists(st) || fs::is_regular_file(st)) return;
  const char* kind = fs::is_fifo(st)        ? "a FIFO (named pipe)"
                     : fs::is_directory(st)  ? "a folder"
                     : fs::is_character_file(st) || fs::is_block_file(st) ? "a device"
                     : fs::is_socket(st)     ? "a socket"
                                             : "not a regular file";
  throw ConfigError(file + ": is " + std::string(kind) + ", not a regular file: inputs are read from files");
}

nlohmann::json load_json_file(const std::string& file) {
  require_regular_file(file);
  std::ifstream in(file);
  if (!in) throw ConfigError("cannot open scenario file '" + file + "'");
  return parse_json_checked(in, "scenario file '" + file + "'", /*allow_comments=*/true);
}

std::string scenario_kind(const std::string& file) {
  const nlohmann::json doc = load_json_file(file);
  if (!doc.is_object()) throw ConfigError("scenario file '" + file + "': expected a JSON object");
  const auto it = doc.find("kind");
  if (it == doc.end()) return "prl";
  if (!it->is_string() || (*it != "prl" && *it != "uav" && *it != "scene"))
    throw ConfigError("scenario file '" + file + "': key 'kind' must be \"prl\", \"uav\" or \"scene\"");
  return it->get<std::string>();
}

void apply_override(nlohmann::json& doc, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError("override '" + assignment + "': expected key.path=value");
  const std::string path = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  nlohmann::json value;
  try {
    value = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error&) {
    value = text;
  } catch (const nlohmann::json::out_of_range&) {
    throw ConfigError("override '" + assignment + "': the number overflows the double range");
  }
  // null would read as "the key left out" (its default), silently: a value is needed
  if (value.is_null())
    throw ConfigError("override '" + assignment + "': null is not a value (give one, or leave the key out for its default)");
  nlohmann::json* node = &doc;
  std::size_t start = 0;
  while (true) {
    const auto dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? dot : dot - start);
    if (part.empty()) throw ConfigError("override '" + assignment + "': empty key component");
    if (!node->is_object()) throw ConfigError("override '" + assignment + "': '" + part +
                                              "' is inside a non-object");
    if (dot == std::string::npos) {
      (*node)[part] = value;
      return;
    }
    node = &(*node)[part];
    if (node->is_null()) *node = nlohmann::json::object();
    start = dot + 1;
  }
}

}  // namespace rnav
