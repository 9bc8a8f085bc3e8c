// Command-line options of a process from one table: the same entries parse the arguments and
// print --help, so the help cannot drift from the parser.
//
//   rnav::cli::Parser p("rnav_clock", "--scenario FILE [options]", "Drives the lock-step ...");
//   p.value("--seed", "S", "ensemble seed", "1", [&](const std::string& v) { seed = ...; });
//   p.flag("--realtime", "pace the simulation to the wall clock", realtime);
//   if (!p.parse(argc, argv, std::cout)) return 0;   // --help or --list-options was answered
//
// Every parser also knows -h/--help (usage and every option, with its unit and default, on
// stdout) and --list-options (each option name, and its value's placeholder, one per line: for
// shell completion and for the test that checks the help against the parser). An unknown option
// is a ConfigError naming it and, if one is near, the option it probably meant. Errors print as
// "PROGRAM: error: message" (guarded_main).
#pragma once

#include "common/io/config.hpp"

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace rnav::cli {

class Parser {
 public:
  /// @param program     the binary's name, e.g. "rnav_clock": the "Usage:" lines and errors
  /// @param synopsis    what follows the program name on the usage line; several usages are
  ///                    separated by '\n' (each printed as its own "PROGRAM ..." line)
  /// @param description what the program does (printed after the usage, wrapped)
  Parser(std::string program, std::string synopsis, std::string description);

  /// An option without a value; `on` is called when it is given.
  Parser& flag(const std::string& name, const std::string& help, std::function<void()> on);
  /// An option without a value that sets `target` to true.
  Parser& flag(const std::string& name, const std::string& help, bool& target);
  /// An option with a value (`--name VALUE` or `--name=VALUE`). `help` states the unit;
  /// `default_text` is printed as "(default ...)" unless empty (say "required" for one that is).
  Parser& value(const std::string& name, const std::string& metavar, const std::string& help,
                const std::string& default_text, std::function<void(const std::string&)> set);
  /// An option whose value is stored as given.
  Parser& value(const std::string& name, const std::string& metavar, const std::string& help,
                const std::string& default_text, std::string& target);
  /// An option that may be repeated; each value is appended to `target`.
  Parser& repeated(const std::string& name, const std::string& metavar, const std::string& help,
                   std::vector<std::string>& target);
  /// An option that may be repeated; `take` is called with each value.
  Parser& repeated(const std::string& name, const std::string& metavar, const std::string& help,
                   std::function<void(const std::string&)> take);
  /// Arguments that are not options (after the program name), in order; `metavar` and `help`
  /// describe them in the help. Without this, any such argument is an error.
  Parser& positionals(const std::string& metavar, const std::string& help,
                      std::function<void(const std::string&)> take);
  /// Text printed after the options (units, notes, pointers); pre-formatted lines.
  Parser& epilog(const std::string& text);

  /// Parse argv[1..argc-1]. -h/--help prints help() to `out`, --list-options the names; both
  /// return false (the caller exits 0). Throws ConfigError for unknown options (each with the
  /// nearest known one), missing values, values given to flags, bad values and unexpected
  /// arguments: all of them, named in one error.
  bool parse(int argc, const char* const* argv, std::ostream& out);
  bool parse(int argc, char** argv, std::ostream& out) {
    return parse(argc, const_cast<const char* const*>(argv), out);
  }

  /// "Usage: ...", the description, every option with its placeholder, help and default.
  std::string help() const;
  /// Every option name (with " METAVAR" for one that takes a value), one per line.
  std::string list() const;
  const std::string& program() const { return program_; }

 private:
  struct Option {
    std::string name, metavar, help, default_text;
    bool repeatable = false;
    std::function<void(const std::string&)> set;  // receives "" for a flag
  };
  const Option* find(const std::string& name) const;

  std::string program_, synopsis_, description_, epilog_;
  std::vector<Option> options_;
  std::string positional_metavar_, positional_help_;
  std::function<void(const std::string&)> positional_;
};

/// A whole finite decimal number within [lo, hi] from an option's text, else a ConfigError
/// naming the option and the text.
double number(const std::string& option, const std::string& text, double lo, double hi);

/// "PROGRAM: error: message" — the one error format of every program.
std::string error_line(const std::string& program, const std::string& message);

/// Run a process's body: its return value is the exit status; a ConfigError (bad input)
/// prints error_line(program, what) on stderr and gives 2, any other exception gives 1.
int guarded_main(const std::string& program, const std::function<int()>& body);

/// Throws ConfigError naming every required argument that is missing, in one error: each entry
/// is (what, given), e.g. {"--scenario FILE", !file.empty()}; "--scenario FILE and --out DIR are
/// required (see PROGRAM --help)". Nothing when every one is given.
void require(const std::string& program, const std::vector<std::pair<std::string, bool>>& args);

}  // namespace rnav::cli
