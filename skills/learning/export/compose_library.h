#pragma once
// Joins chosen skills of several libraries into one. Each skill keeps the policy that trained it,
// so one library can serve what separate runs discovered: one seed's forward gaits beside
// another's backward gaits and turns. The policies run behind one target filter, so the parts
// must agree on it; evaluations of the result use the first policy's training environment.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace flsd {

struct LibraryPart {
  std::string path;
  std::vector<int> skills;  // the skill ids to take, in this order; empty: all of them
};

// "PATH" (every skill) or "PATH:K,K,..." (those skills); the list follows the last ':', so a path
// that holds a colon needs a list. Throws InputError naming the text on a malformed list.
LibraryPart ParseLibraryPart(const std::string& text);

// Writes the joined library to `output` (atomically) and returns what it holds: for each new skill
// the file and skill it came from. A chosen skill's mirror image must be chosen too, so that mirror
// pairs stay pairs. A part's learned selector is not carried over: it chose among other skills.
// Throws InputError naming the file and skill for anything it cannot join.
nlohmann::json ComposeLibraries(const std::vector<LibraryPart>& parts, const std::string& output);

}  // namespace flsd
