#include "params/io/suggest.h"

#include <algorithm>
#include <array>

namespace scw::params {

#if defined(__clang__)
// Fuzz builds: the comparisons of the distance table are no branches worth exploring, and tracing
// them took 60 % of the YAML fuzz targets' time.
#define SCW_NO_FUZZ_COVERAGE __attribute__((no_sanitize("coverage")))
#else
#define SCW_NO_FUZZ_COVERAGE
#endif

namespace {
// Three rows of the table over b (the transposition looks two rows back), rotated by pointer.
// Stops as soon as no later cell can fall below the limit: every cell of row i+1 comes from row i
// (+0 or +1) or, by a transposition, from row i-1 (+1).
SCW_NO_FUZZ_COVERAGE std::size_t Distance(std::string_view a, std::string_view b, std::size_t limit,
                                          std::size_t* back, std::size_t* prev, std::size_t* cur) {
  const std::size_t lb = b.size();
  for (std::size_t j = 0; j <= lb; ++j) prev[j] = j;
  std::size_t prev_min = 0;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    std::size_t row_min = i;
    for (std::size_t j = 1; j <= lb; ++j) {
      const std::size_t del = prev[j] + 1, ins = cur[j - 1] + 1;
      const std::size_t rep = prev[j - 1] + (a[i - 1] != b[j - 1] ? 1u : 0u);
      std::size_t d = del < ins ? (del < rep ? del : rep) : (ins < rep ? ins : rep);
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && back[j - 2] + 1 < d)
        d = back[j - 2] + 1;
      cur[j] = d;
      if (d < row_min) row_min = d;
    }
    if (row_min >= limit && prev_min + 1 >= limit) return limit;
    prev_min = row_min;
    std::size_t* oldest = back;
    back = prev;
    prev = cur;
    cur = oldest;
  }
  return prev[lb];
}
}  // namespace

std::size_t EditDistance(std::string_view a, std::string_view b, std::size_t limit) {
  const std::size_t la = a.size(), lb = b.size();
  if ((la > lb ? la - lb : lb - la) >= limit) return limit;  // at least the length difference
  constexpr std::size_t kSmall = 128;
  if (lb < kSmall) {
    std::array<std::size_t, 3 * kSmall> rows;
    return Distance(a, b, limit, rows.data(), rows.data() + kSmall, rows.data() + 2 * kSmall);
  }
  std::vector<std::size_t> rows(3 * (lb + 1));
  return Distance(a, b, limit, rows.data(), rows.data() + lb + 1, rows.data() + 2 * (lb + 1));
}

std::string ClosestWord(std::string_view word, const std::vector<std::string_view>& candidates,
                        std::size_t limit) {
  std::string_view best;
  bool found = false;
  for (const std::string_view c : candidates) {
    const std::size_t d = EditDistance(word, c, limit);
    if (d < limit) {
      limit = d;
      best = c;
      found = true;
    }
  }
  return found ? std::string(best) : std::string();
}

}  // namespace scw::params
