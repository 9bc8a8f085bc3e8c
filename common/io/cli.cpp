#include "common/io/cli.hpp"

#include "common/io/decimal.hpp"

#include "common/io/did_you_mean.hpp"

#include <cctype>
#include <cmath>
#include <iostream>
#include <sstream>

namespace rnav::cli {

namespace {

constexpr std::size_t kWidth = 100;   // help text is wrapped at this many columns
constexpr std::size_t kColumn = 26;   // option descriptions start in this column

// Words of `text` wrapped to kWidth, every line after the first indented by `indent` spaces,
// the first continuing at column `first_col`.
std::string wrap(const std::string& text, std::size_t indent, std::size_t first_col) {
  std::istringstream in(text);
  std::string out, word;
  std::size_t col = first_col;
  bool line_empty = true;
  while (in >> word) {
    if (!line_empty && col + 1 + word.size() > kWidth) {
      out += "\n" + std::string(indent, ' ');
      col = indent;
      line_empty = true;
    }
    if (!line_empty) out += ' ', ++col;
    out += word;
    col += word.size();
    line_empty = false;
  }
  return out;
}

// Paragraphs (separated by blank lines) wrapped; a line starting with a space is kept as it is.
std::string wrap_paragraphs(const std::string& text) {
  std::istringstream in(text);
  std::string out, para, line;
  auto flush = [&]() {
    if (!para.empty()) out += wrap(para, 0, 0) + "\n";
    para.clear();
  };
  while (std::getline(in, line)) {
    if (line.empty()) {
      flush();
      out += "\n";
    } else if (line[0] == ' ') {
      flush();
      out += line + "\n";
    } else {
      para += (para.empty() ? "" : " ") + line;
    }
  }
  flush();
  return out;
}

}  // namespace

Parser::Parser(std::string program, std::string synopsis, std::string description)
    : program_(std::move(program)), synopsis_(std::move(synopsis)), description_(std::move(description)) {}

Parser& Parser::flag(const std::string& name, const std::string& help, std::function<void()> on) {
  options_.push_back({name, "", help, "", false, [on](const std::string&) { on(); }});
  return *this;
}

Parser& Parser::flag(const std::string& name, const std::string& help, bool& target) {
  return flag(name, help, [&target]() { target = true; });
}

Parser& Parser::value(const std::string& name, const std::string& metavar, const std::string& help,
                      const std::string& default_text, std::function<void(const std::string&)> set) {
  options_.push_back({name, metavar, help, default_text, false, std::move(set)});
  return *this;
}

Parser& Parser::value(const std::string& name, const std::string& metavar, const std::string& help,
                      const std::string& default_text, std::string& target) {
  return value(name, metavar, help, default_text, [&target](const std::string& v) { target = v; });
}

Parser& Parser::repeated(const std::string& name, const std::string& metavar, const std::string& help,
                         std::vector<std::string>& target) {
  return repeated(name, metavar, help, [&target](const std::string& v) { target.push_back(v); });
}

Parser& Parser::repeated(const std::string& name, const std::string& metavar, const std::string& help,
                         std::function<void(const std::string&)> take) {
  options_.push_back({name, metavar, help, "", true, std::move(take)});
  return *this;
}

Parser& Parser::positionals(const std::string& metavar, const std::string& help,
                            std::function<void(const std::string&)> take) {
  positional_metavar_ = metavar;
  positional_help_ = help;
  positional_ = std::move(take);
  return *this;
}

Parser& Parser::epilog(const std::string& text) {
  epilog_ += (epilog_.empty() ? "" : "\n") + text;
  return *this;
}

const Parser::Option* Parser::find(const std::string& name) const {
  for (const auto& o : options_)
    if (o.name == name) return &o;
  return nullptr;
}

bool Parser::parse(int argc, const char* const* argv, std::ostream& out) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      out << help();
      return false;
    }
    if (a == "--list-options") {
      out << list();
      return false;
    }
  }
  // Every unknown option and every malformed one is collected and named in one error at the end.
  std::vector<std::string> unknown, errors;
  bool unknown_unguessed = false;
  std::vector<std::string> names{"--help", "--list-options"};
  for (const auto& x : options_) names.push_back(x.name);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.size() < 2 || a[0] != '-' || (a[1] != '-' && std::isdigit(static_cast<unsigned char>(a[1])))) {
      if (!positional_) {
        errors.push_back("unexpected argument '" + a + "' (see " + program_ + " --help)");
        continue;
      }
      if (!unknown.empty()) continue;  // it may be an unknown option's value
      try {
        positional_(a);
      } catch (const ConfigError& e) {
        errors.push_back(e.what());
      }
      continue;
    }
    const auto eq = a.find('=');
    const std::string name = eq == std::string::npos ? a : a.substr(0, eq);
    const Option* o = find(name);
    if (!o) {
      const std::string hint = did_you_mean(name, names);
      unknown_unguessed = unknown_unguessed || hint.empty();
      unknown.push_back("'" + a + "'" + hint);
      continue;
    }
    std::string value;
    if (o->metavar.empty()) {
      if (eq != std::string::npos) {
        errors.push_back("option " + name + " takes no value, got '" + a + "'");
        continue;
      }
    } else if (eq != std::string::npos) {
      value = a.substr(eq + 1);
    } else {
      if (i + 1 >= argc) {
        errors.push_back("option " + name + " needs a value (" + o->metavar + ")");
        continue;
      }
      value = argv[++i];
    }
    try {
      o->set(value);
    } catch (const ConfigError& e) {  // a bad value, named; the other options still checked
      errors.push_back(e.what());
    }
  }
  std::string msg;
  if (!unknown.empty()) {
    msg = unknown.size() == 1 ? "unknown option " : "unknown options ";
    for (std::size_t k = 0; k < unknown.size(); ++k) msg += (k ? ", " : "") + unknown[k];
    if (unknown_unguessed) msg += " (see " + program_ + " --help)";
  }
  for (const auto& e : errors) {
    // a word after an unknown option may be its value: not named as unexpected then
    if (!unknown.empty() && e.rfind("unexpected argument ", 0) == 0) continue;
    msg += (msg.empty() ? "" : "; ") + e;
  }
  if (!msg.empty()) throw ConfigError(msg);
  return true;
}

std::string Parser::help() const {
  std::ostringstream o;
  std::istringstream syn(synopsis_);
  std::string line;
  bool first = true;
  while (std::getline(syn, line)) {
    o << (first ? "Usage: " : "       ") << program_ << (line.empty() ? "" : " " + line) << "\n";
    first = false;
  }
  if (first) o << "Usage: " << program_ << "\n";
  if (!description_.empty()) o << "\n" << wrap_paragraphs(description_);
  auto entry = [&](const std::string& left, const std::string& text) {
    std::string l = "  " + left;
    if (l.size() + 2 > kColumn) {
      o << l << "\n" << std::string(kColumn, ' ');
    } else {
      o << l << std::string(kColumn - l.size(), ' ');
    }
    o << wrap(text, kColumn, kColumn) << "\n";
  };
  if (positional_) {
    o << "\nArguments:\n";
    entry(positional_metavar_, positional_help_);
  }
  o << "\nOptions:\n";
  for (const auto& x : options_) {
    std::string text = x.help;
    if (x.repeatable) text += " (repeatable)";
    if (!x.default_text.empty())
      text += x.default_text == "required" ? " (required)" : " (default " + x.default_text + ")";
    entry(x.name + (x.metavar.empty() ? "" : " " + x.metavar), text);
  }
  entry("-h, --help", "print this help and exit");
  entry("--list-options", "print the option names, one per line, and exit");
  if (!epilog_.empty()) o << "\n" << wrap_paragraphs(epilog_);
  return o.str();
}

std::string Parser::list() const {
  std::string s;
  for (const auto& x : options_) s += x.name + (x.metavar.empty() ? "" : " " + x.metavar) + "\n";
  return s + "-h\n--help\n--list-options\n";
}

double number(const std::string& option, const std::string& text, double lo, double hi) {
  double x = NAN;
  std::string why;
  if (!parse_decimal(text, x, why)) throw ConfigError(option + ": '" + text + "' is not a finite number (" + why + ")");
  if (x < lo || x > hi)
    throw ConfigError(option + ": " + text + " is outside [" + value_text(lo) + ", " + value_text(hi) + "]");
  return x;
}

std::string error_line(const std::string& program, const std::string& message) {
  return program + ": error: " + message;
}

int guarded_main(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& e) {
    std::cerr << error_line(program, e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << error_line(program, e.what()) << "\n";
    return 1;
  }
}

void require(const std::string& program, const std::vector<std::pair<std::string, bool>>& args) {
  std::vector<std::string> missing;
  for (const auto& [what, given] : args)
    if (!given) missing.push_back(what);
  if (missing.empty()) return;
  std::string m;
  for (std::size_t i = 0; i < missing.size(); ++i)
    m += (i == 0 ? "" : i + 1 == missing.size() ? " and " : ", ") + missing[i];
  throw ConfigError(m + (missing.size() > 1 ? " are" : " is") + " required (see " + program + " --help)");
}

}  // namespace rnav::cli
