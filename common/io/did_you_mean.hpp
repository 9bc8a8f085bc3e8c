// "Did you mean ...?": the closest known name to a misspelt one (an option, a scenario key, a
// scenario name), by edit distance. Used by the option parser (cli.hpp) and the scenario reader
// (config.hpp); scripts use the same rule (scripts/cli.bash, scripts/rnav/cli_args.py).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace rnav {

/// Optimal-string-alignment distance: the fewest insertions, deletions, substitutions and swaps
/// of two adjacent characters that turn a into b.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The candidate nearest to `word` if it is near enough to be a typo of it: at most
/// max(1, n / 3) edits away, n the length of `word` without leading '-' (so `pape` -> `paper`,
/// `radar.x_n` -> `radar.x_m`, `--sed` -> `--seed`); the first of equally near ones; "" if none.
std::string closest_name(const std::string& word, const std::vector<std::string>& candidates);

/// " (did you mean 'X'?)" for the closest candidate, or "" when none is near.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace rnav
