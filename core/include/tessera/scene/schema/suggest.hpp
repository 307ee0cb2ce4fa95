#pragma once
#include <span>
#include <string>
#include <string_view>

namespace tessera::schema {

// The candidate closest to `word` by edit distance (insertions, deletions, substitutions and
// swaps of neighbours), if it is close enough to be a likely misspelling: at most 1 edit for
// words up to 4 letters, 2 up to 8, 3 beyond. Empty when none is.
std::string closest_match(std::string_view word, std::span<const std::string_view> candidates);

// " (did you mean 'radius'?)", or "" when nothing is close.
std::string did_you_mean(std::string_view word, std::span<const std::string_view> candidates);

}  // namespace tessera::schema
