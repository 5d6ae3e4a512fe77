#pragma once
// "Did you mean ...?" for a name typed on the command line: the known name nearest to what was typed.
#include <string>
#include <vector>

namespace sb {

// The optimal-string-alignment distance between a and b: insertions, deletions, substitutions and swaps of
// two neighbouring characters each cost one ("evalute" -> "evaluate" is 1, "fost" -> "fots" is 1).
int edit_distance(const std::string& a, const std::string& b);

// The name of `known` nearest to `typed`, when it is near enough to be a slip of the keyboard: at most
// max(1, |typed| / 3) edits (a third of the word, so "fit" does not suggest "gui"), ties to the first in
// `known`; "" when none is. Comparison ignores ASCII case.
std::string closest_name(const std::string& typed, const std::vector<std::string>& known);

// " (did you mean 'NAME'?)" for closest_name's answer, "" when there is none: ready to append to an error.
std::string did_you_mean(const std::string& typed, const std::vector<std::string>& known);

}  // namespace sb
