// The one number parser of the project's text inputs (CSV cells, command-line options): decimal
// only, the whole text consumed, finite.
//   [+-] digits [. digits] [(e|E) [+-] digits]   or   [+-] . digits [exponent]
// Refused, each with its reason: an empty text, hexadecimal ("0x1.0p+15" is 32768 to strtod),
// inf, nan, null, spaces or anything after the number, and a value beyond the double range
// ("1e400": overflow, not infinity). A denormal is accepted (it is a finite number).
#pragma once

#include <string>

namespace rnav {

/// true and x = the value of `text` if it is a finite decimal number; else false and `why`
/// says what is wrong ("not a decimal number", "overflows the double range").
bool parse_decimal(const std::string& text, double& x, std::string& why);

}  // namespace rnav
