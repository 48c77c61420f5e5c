// Suggestions for misspelt names ("did you mean 'building'?"): the candidate closest to what the
// user typed, when it is close enough to be a likely typo.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rigsim {

// Edit distance (insertions, deletions, substitutions, and swaps of two neighbouring letters),
// ignoring letter case.
int EditDistance(std::string_view a, std::string_view b);

// The candidate nearest to `typed` when its distance is at most a third of the longer name
// (at least 1, at most 3); nullopt otherwise. Ties go to the earlier candidate.
std::optional<std::string> ClosestName(std::string_view typed, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" when nothing is close: to append to an error message.
std::string DidYouMean(std::string_view typed, const std::vector<std::string>& candidates);

}  // namespace rigsim
