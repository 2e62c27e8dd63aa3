#pragma once
// What skillweb sends the page, as JSON: one state sample per server-sent event, the replies to
// the page's calls, the library's skills and the navigation map. Field names follow client/types.h.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "client/types.h"
#include "navigation_map/map2d.h"

namespace flsd::web {

nlohmann::json ToJson(const StateReport& state);
nlohmann::json ToJson(const Reply& reply);
nlohmann::json ToJson(const std::vector<SkillInfo>& skills);
nlohmann::json ToJson(const Map2D& map);

}  // namespace flsd::web
