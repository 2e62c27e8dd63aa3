#include "client/web/web_json.h"

namespace flsd::web {

using nlohmann::json;

json ToJson(const StateReport& s) {
  const TaskReport& t = s.task;
  return {{"time", s.time},
          {"tick", s.tick},
          {"backend", s.backend},
          {"mode", Name(s.mode)},
          {"skill", s.skill},
          {"position", s.position},
          {"orientation", s.orientation},
          {"linear_velocity", s.linear_velocity},
          {"angular_velocity", s.angular_velocity},
          {"joint_position", s.joint_position},
          {"joint_velocity", s.joint_velocity},
          {"foot_contact", s.foot_contact},
          {"faults", s.faults},
          {"fault_message", s.fault_message},
          {"controller", s.controller},
          {"deadline_misses", s.deadline_misses},
          {"task",
           {{"client_id", t.client_id},
            {"request_id", t.request_id},
            {"call", t.call},
            {"state", Name(t.state)},
            {"elapsed", t.elapsed},
            {"remaining", t.remaining},
            {"message", t.message},
            {"path", t.path}}}};
}

json ToJson(const Reply& r) {
  return {{"ok", r.ok()}, {"status", Name(r.status)}, {"message", r.message}, {"safety_report", r.safety_report},
          {"request_id", r.request_id}};
}

json ToJson(const std::vector<SkillInfo>& skills) {
  json list = json::array();
  for (const SkillInfo& k : skills) {
    list.push_back({{"id", k.id},
                    {"linear_velocity", k.linear_velocity},
                    {"angular_velocity", k.angular_velocity},
                    {"base_height", k.base_height},
                    {"gait_frequency", k.gait_frequency},
                    {"survival_steps", k.survival_steps}});
  }
  return list;
}

json ToJson(const Map2D& map) {
  json circles = json::array(), polygons = json::array();
  for (const Map2D::Circle& c : map.circles) circles.push_back({{"center", {c.center.x(), c.center.y()}}, {"radius", c.radius}});
  for (const Map2D::Polygon& p : map.polygons) {
    json points = json::array();
    for (const auto& v : p) points.push_back({v.x(), v.y()});
    polygons.push_back(points);
  }
  return {{"bounds", {map.x_min, map.x_max, map.y_min, map.y_max}},
          {"robot_radius", map.robot_radius},
          {"circles", circles},
          {"polygons", polygons}};
}

}  // namespace flsd::web
