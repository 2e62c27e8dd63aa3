#pragma once
// skillweb's routes: the page and its files, the state stream, the library's skills and map, and
// the motion calls, which go to skilld through flsd::Client like any other client's. Every call
// that moves the robot takes the control lease first; damp and clear_stop need none.
//
//   GET  /  /app.js  /style.css  /a1.urdf      the page (built into `page_dir`) and the robot
//   GET  /api/info                             joint names, the map, this client's id
//   GET  /api/skills                           the library's skills
//   GET  /api/events                           the state topic, one server-sent event per sample
//   POST /api/<call>                           stand, stop, reset, damp, clear_stop, release_control,
//                                              execute_skill, track_velocity, navigate (JSON body)

#include <optional>
#include <string>

#include "client/client.h"
#include "client/web/http_server.h"
#include "client/web/state_feed.h"
#include "navigation_map/map2d.h"

namespace flsd::web {

struct WebAppOptions {
  std::string page_dir;   // index.html, app.js, style.css
  std::string urdf_path;  // robot/a1/a1.urdf
  std::optional<Map2D> map;
  // Listening on loopback: requests must name a loopback host, so that a web page elsewhere
  // cannot reach skillweb by pointing a domain name of its own at 127.0.0.1.
  bool loopback_only = true;
};

class WebApp {
 public:
  WebApp(Client& client, WebAppOptions options);
  HttpResponse Handle(const HttpRequest& request);

 private:
  HttpResponse File(const std::string& path, const std::string& content_type) const;
  HttpResponse Events() const;
  HttpResponse Call(const std::string& name, const std::string& body);
  bool Trusted(const HttpRequest& request) const;

  Client& client_;
  WebAppOptions options_;
  StateFeed feed_;
};

}  // namespace flsd::web
