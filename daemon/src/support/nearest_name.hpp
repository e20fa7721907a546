#pragma once
// The known name nearest to a mistyped one, for "did you mean" in messages.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace spinewatch {

// Levenshtein distance: insertions, deletions and substitutions, one each.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The name of `known` nearest to `typed` when at most `allowed` edits apart;
// nothing otherwise, or when two are equally near.
std::optional<std::string> nearest_name(std::string_view typed, const std::vector<std::string>& known,
                                        std::size_t allowed);

// The edits a typo of `word` may take: a third of its length, 1 to 3.
std::size_t typo_allowance(std::string_view word);

}  // namespace spinewatch
