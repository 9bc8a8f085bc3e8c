// Scenario configuration: JSON files with sections, strict validation.
//
// Every key read is recorded; Section::finish() throws for any key that was not read,
// so a misspelt key is an error naming it, never silently ignored. Numbers are checked
// for type, finiteness and range, and errors name the full key path (e.g. "prl.period_s").
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <set>
#include <stdexcept>
#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace rnav {

/// Bad user input in a scenario or on the command line. what() names the culprit.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A view of one JSON object (a scenario section) that records which keys were read.
class Section {
 public:
  /// @param j     the JSON object (must be an object, else ConfigError)
  /// @param path  full key path of this section, used in error messages ("" for the root)
  Section(const nlohmann::json& j, std::string path);

  /// A finite number in [lo, hi]; `def` when the key is absent.
  double number(const std::string& key, double def, double lo, double hi);
  /// A required finite number in [lo, hi].
  double required_number(const std::string& key, double lo, double hi);
  /// An integer in [lo, hi]; `def` when absent.
  long integer(const std::string& key, long def, long lo, long hi);
  bool boolean(const std::string& key, bool def);
  std::string string(const std::string& key, const std::string& def);
  /// A list of [begin, end] pairs of finite numbers in [lo, hi] with begin < end.
  std::vector<std::pair<double, double>> intervals(const std::string& key, double lo, double hi);
  /// A list of finite numbers in [lo, hi]; `def` when absent.
  std::vector<double> numbers(const std::string& key, const std::vector<double>& def, double lo,
                              double hi);
  /// A list of strings; `def` when absent.
  std::vector<std::string> strings(const std::string& key, const std::vector<std::string>& def);
  /// A list of rows of 4 finite numbers each.
  std::vector<std::array<double, 4>> rows4(const std::string& key);
  /// A nested section; an absent key gives an empty section.
  Section section(const std::string& key);
  bool has(const std::string& key) const;

  /// Throws ConfigError naming every key of this section that was never read. A nested section
  /// (from section()) does not throw: its unknown keys wait for the finish() of the section it
  /// came from, which names them together with its own, so a document's unknown keys in several
  /// sections are named in one error (the root's finish() must therefore be called last).
  void finish() const;
  /// Throws ConfigError naming the unknown keys of the nested sections finished so far, not this
  /// section's own: for a reader of only some sections of a document, which cannot finish() it.
  void finish_nested() const;

  const std::string& path() const { return path_; }
  std::string key_path(const std::string& key) const;

 private:
  const nlohmann::json* find(const std::string& key);
  double as_number(const std::string& key, const nlohmann::json& v, double lo, double hi) const;

  nlohmann::json j_;
  std::string path_;
  std::set<std::string> used_;
  /// The unknown keys of finished nested sections, shared by a root and every section nested in it.
  std::shared_ptr<std::vector<std::string>> deferred_ = std::make_shared<std::vector<std::string>>();
  bool nested_ = false;
};

/// The scenario kind of a file: its top-level "kind" ("prl" when absent).
/// [levels] JSON nesting allowed in any input (scenarios: 4; Autoferry and ADS-B files: 3).
inline constexpr int kMaxJsonDepth = 64;
/// Parse JSON text from an input, rejecting a key repeated within one object (naming it and
/// `source`) and nesting deeper than kMaxJsonDepth (checked while parsing, before a deep value
/// exists). Throws ConfigError naming `source` on any error.
nlohmann::json parse_json_checked(std::istream& in, const std::string& source, bool allow_comments);
nlohmann::json parse_json_checked(const std::string& text, const std::string& source, bool allow_comments);

/// A command-line integer: the whole text a decimal integer within [lo, hi], else ConfigError
/// naming the option and the text (no silent truncation: 4294967297 is not 1).
long long parse_integer(const std::string& option, const std::string& text, long long lo, long long hi);

/// x with 10 significant digits, as error messages quote values.
std::string value_text(double x);

std::string scenario_kind(const std::string& file);

/// Load a JSON file; errors name the file and the parse position.
nlohmann::json load_json_file(const std::string& file);

/// Throws ConfigError if `file` exists and is not a regular file (a FIFO, a device, a socket, a
/// folder), naming its type: opening a FIFO blocks until someone writes to it, a device may
/// never end. A missing file passes (the opener names it).
void require_regular_file(const std::string& file);

/// Apply an override "a.b.c=value" to a JSON document. `value` is parsed as JSON when it
/// parses (numbers, true/false, arrays), otherwise taken as a string.
void apply_override(nlohmann::json& doc, const std::string& assignment);

}  // namespace rnav
