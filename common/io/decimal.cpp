#include "common/io/decimal.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace rnav {

namespace {

bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// Whether all of s follows the grammar of decimal.hpp.
bool decimal_syntax(const std::string& s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t mantissa = 0;
  while (i < s.size() && digit(s[i])) ++i, ++mantissa;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && digit(s[i])) ++i, ++mantissa;
  }
  if (mantissa == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t exponent = 0;
    while (i < s.size() && digit(s[i])) ++i, ++exponent;
    if (exponent == 0) return false;
  }
  return i == s.size();
}

}  // namespace

bool parse_decimal(const std::string& text, double& x, std::string& why) {
  if (!decimal_syntax(text)) {
    why = "not a decimal number";
    return false;
  }
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1)) {
    why = "overflows the double range";
    return false;
  }
  x = v;
  return true;
}

}  // namespace rnav
