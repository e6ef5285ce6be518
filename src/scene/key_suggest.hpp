#pragma once
// "Did you mean": the valid key closest to a misspelt one (scene keys, issue 35).
#include <optional>
#include <string>
#include <vector>

namespace varsph::scene {

// Levenshtein distance (insertions, deletions, substitutions), ASCII case-insensitive.
std::size_t edit_distance(const std::string& a, const std::string& b);

// The candidate closest to `word` when it is close enough to be a typo of it: at most 1 edit for words of up
// to 4 letters, 2 up to 8, 3 beyond ("particle" -> "particles", "tolerence" -> "tolerance"), or one is the
// other cut short (3+ letters: "rotate" -> "rotate_deg"); a tie goes to the first candidate. None when
// nothing is that close, or `word` is itself a candidate.
std::optional<std::string> closest_key(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace varsph::scene
