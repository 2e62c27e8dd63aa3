#include "client/web/web_app.h"

#include <fstream>
#include <functional>
#include <sstream>

#include "client/web/web_json.h"
#include "comm/protocol.h"
#include "robot/a1.h"

namespace flsd::web {
namespace {

using nlohmann::json;

// The host part of a Host header ("127.0.0.1:8090" -> "127.0.0.1").
std::string HostName(const std::string& host) { return host.substr(0, host.rfind(':')); }

HttpResponse Refused(int status, const std::string& why) {
  return HttpResponse::Json(status, json{{"ok", false}, {"status", "refused"}, {"message", why}}.dump());
}

}  // namespace

WebApp::WebApp(Client& client, WebAppOptions options) : client_(client), options_(std::move(options)), feed_(client) {}

HttpResponse WebApp::Handle(const HttpRequest& request) {
  if (!Trusted(request)) return Refused(403, "request from another site or host name");
  const std::string& path = request.path;
  if (request.method == "POST" && path.rfind("/api/", 0) == 0) return Call(path.substr(5), request.body);
  if (request.method != "GET") return HttpResponse::Text(405, "method not allowed\n");
  if (path == "/" || path == "/index.html") return File(options_.page_dir + "/index.html", "text/html; charset=utf-8");
  if (path == "/app.js") return File(options_.page_dir + "/app.js", "text/javascript; charset=utf-8");
  if (path == "/style.css") return File(options_.page_dir + "/style.css", "text/css; charset=utf-8");
  if (path == "/a1.urdf") return File(options_.urdf_path, "application/xml");
  if (path == "/api/events") return Events();
  if (path == "/api/info") {
    json info{{"client_id", client_.id()}, {"joint_names", a1::kJointNames}, {"map", nullptr}};
    if (options_.map) info["map"] = ToJson(*options_.map);
    return HttpResponse::Json(200, info.dump());
  }
  if (path == "/api/skills") {
    try {
      return HttpResponse::Json(200, ToJson(client_.ListSkills()).dump());
    } catch (const CallError& e) {
      return HttpResponse::Json(503, ToJson(e.reply()).dump());
    }
  }
  return HttpResponse::Text(404, "not found\n");
}

bool WebApp::Trusted(const HttpRequest& request) const {
  const std::string host = request.Header("host");
  if (options_.loopback_only && HostName(host) != "127.0.0.1" && HostName(host) != "localhost") return false;
  if (request.method != "POST") return true;
  // A cross-site form or fetch cannot send JSON without a CORS preflight, which is never granted.
  const std::string origin = request.Header("origin");
  return request.Header("content-type").rfind("application/json", 0) == 0 &&
         (origin.empty() || origin == "http://" + host);
}

HttpResponse WebApp::File(const std::string& path, const std::string& content_type) const {
  std::ifstream in(path, std::ios::binary);
  if (!in) return HttpResponse::Text(404, "missing " + path + "\n");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  HttpResponse r = HttpResponse::Text(200, bytes.str());
  r.content_type = content_type;
  return r;
}

HttpResponse WebApp::Events() const {
  HttpResponse r;
  r.content_type = "text/event-stream";
  r.stream = [this](HttpStream& out) {
    uint64_t seen = 0;
    while (out.open()) {
      const std::string event = feed_.Next(seen, seen, std::chrono::milliseconds(1000));
      // A comment line while no state comes keeps proxies from closing the stream and tells
      // this thread when the page has gone.
      if (!out.Write(event.empty() ? std::string(":\n\n") : event)) return;
    }
  };
  return r;
}

HttpResponse WebApp::Call(const std::string& name, const std::string& body) {
  const std::optional<flsd::Call> call = FindCall(name);
  std::function<Reply()> make;
  try {
    const json args = body.empty() ? json::object() : json::parse(body);
    if (!args.is_object()) return Refused(400, "the body is not a JSON object");
    const auto number = [&](const char* key) { return args.value(key, 0.0); };
    switch (call.value_or(flsd::Call::kStatus)) {
      case flsd::Call::kDamp: make = [this] { return client_.Damp(); }; break;
      case flsd::Call::kClearStop: make = [this] { return client_.ClearStop(); }; break;
      case flsd::Call::kReleaseControl: make = [this] { return client_.ReleaseControl(); }; break;
      case flsd::Call::kStand: make = [this] { return client_.Stand(); }; break;
      case flsd::Call::kStop: make = [this] { return client_.Stop(); }; break;
      case flsd::Call::kReset: make = [this] { return client_.Reset(); }; break;
      case flsd::Call::kExecuteSkill: {
        const int skill = args.at("skill").get<int>();
        const double duration = number("duration");
        make = [this, skill, duration] { return client_.ExecuteSkill(skill, duration).reply(); };
        break;
      }
      case flsd::Call::kTrackVelocity: {
        const double vx = number("vx"), vy = number("vy"), wz = number("wz"), duration = number("duration");
        make = [=] { return client_.TrackVelocity(vx, vy, wz, duration).reply(); };
        break;
      }
      case flsd::Call::kNavigate: {
        const double x = args.at("x").get<double>(), y = args.at("y").get<double>();
        make = [this, x, y] { return client_.Navigate(x, y).reply(); };
        break;
      }
      default:  // the lease is skillweb's to keep; skills and status have routes of their own
        return Refused(404, "not a call the page makes: " + name);
    }
  } catch (const json::exception& e) {
    return Refused(400, std::string("bad arguments: ") + e.what());
  }
  // Like any client: take the lease (or keep it) before a call that needs it.
  Reply reply = Spec(*call).needs_control ? client_.AcquireControl() : Reply{};
  if (!Spec(*call).needs_control || reply.ok()) reply = make();
  return HttpResponse::Json(200, ToJson(reply).dump());
}

}  // namespace flsd::web
