#include "client/web/page_link.h"

#include <functional>

#include "client/web/web_json.h"
#include "comm/protocol.h"

namespace flsd::web {

using nlohmann::json;

json LocalPageLink::Command(const std::string& name, const std::string& body, int& status) {
  const auto refused = [&status](int code, const std::string& why) {
    status = code;
    return json{{"ok", false}, {"status", "refused"}, {"message", why}, {"audit", "refused: " + why}};
  };
  Client& client = client_;
  const std::optional<flsd::Call> call = FindCall(name);
  std::function<flsd::Reply()> make;
  try {
    const json args = body.empty() ? json::object() : json::parse(body);
    if (!args.is_object()) return refused(400, "the body is not a JSON object");
    const auto number = [&](const char* key) { return args.value(key, 0.0); };
    switch (call.value_or(flsd::Call::kStatus)) {
      case flsd::Call::kDamp: make = [&client] { return client.Damp(); }; break;
      case flsd::Call::kClearStop: make = [&client] { return client.ClearStop(); }; break;
      case flsd::Call::kReleaseControl: make = [&client] { return client.ReleaseControl(); }; break;
      case flsd::Call::kStand: make = [&client] { return client.Stand(); }; break;
      case flsd::Call::kStop: make = [&client] { return client.Stop(); }; break;
      case flsd::Call::kReset: make = [&client] { return client.Reset(); }; break;
      case flsd::Call::kExecuteSkill: {
        const int skill = args.at("skill").get<int>();
        const double duration = number("duration");
        make = [&client, skill, duration] { return client.ExecuteSkill(skill, duration).reply(); };
        break;
      }
      case flsd::Call::kTrackVelocity: {
        const double vx = number("vx"), vy = number("vy"), wz = number("wz"), duration = number("duration");
        make = [&client, vx, vy, wz, duration] { return client.TrackVelocity(vx, vy, wz, duration).reply(); };
        break;
      }
      case flsd::Call::kNavigate: {
        const double x = args.at("x").get<double>(), y = args.at("y").get<double>();
        make = [&client, x, y] { return client.Navigate(x, y).reply(); };
        break;
      }
      default:  // the lease is the page's to keep; skills and status have routes of their own
        return refused(404, "not a call the page makes: " + name);
    }
  } catch (const json::exception& e) {
    return refused(400, std::string("bad arguments: ") + e.what());
  }
  // Like any client: take the page's lease (or keep it) before a call that needs it.
  flsd::Reply reply = Spec(*call).needs_control ? client.AcquireControl() : flsd::Reply{};
  if (!Spec(*call).needs_control || reply.ok()) reply = make();
  json answer = ToJson(reply);
  answer["audit"] = reply.Describe();
  return answer;
}

json LocalPageLink::Skills(int& status) {
  try {
    status = 200;
    return ToJson(client_.ListSkills());
  } catch (const CallError& e) {
    status = 503;
    return ToJson(e.reply());
  }
}

}  // namespace flsd::web
