// "Did you mean …?" for every place that names an unknown word: parameter keys, `--set` keys,
// log columns, sub-commands. One edit distance for the whole workspace.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace scw::params {

/// Edit distance of a and b counting insertions, deletions, substitutions and swaps of two
/// neighbouring characters (optimal string alignment: "tnue" is one edit from "tune") when it is
/// below `limit`; otherwise some value ≥ `limit` (the search stops early). Allocation-free for
/// words of up to 127 characters.
std::size_t EditDistance(std::string_view a, std::string_view b,
                         std::size_t limit = std::numeric_limits<std::size_t>::max());

/// The candidate closest to `word` with a distance below `limit` (the first of equals), or empty.
std::string ClosestWord(std::string_view word, const std::vector<std::string_view>& candidates,
                        std::size_t limit);

}  // namespace scw::params
