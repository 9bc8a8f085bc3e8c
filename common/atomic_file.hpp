// Results are never left half-written: write to a hidden temporary, then rename into place.
#pragma once

#include <string>

namespace rnav {

/// Write `text` to dir/name via dir/.name.partial and an atomic rename; throws on failure.
void write_file_atomic(const std::string& dir, const std::string& name, const std::string& text);

/// printf("%.*f") as a string.
std::string fixed(double x, int prec = 6);

}  // namespace rnav
