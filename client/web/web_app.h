#pragma once
// skillweb's routes: the page and its files, logins, the state stream, the library's skills and
// map, and the motion calls, which go to skilld through the page's own flsd::Client like any
// other client's. Every call that moves the robot takes the page's control lease first; damp and
// clear_stop need none.
//
//   GET  /  /app.js  /style.css  /a1.urdf      the page (built into `page_dir`) and the robot
//   POST /api/login {name, password}           opens a session: its cookie, CSRF token and client
//   GET  /api/session                          who this page is, its role and CSRF token (or logged_in false)
//   POST /api/logout                           closes the session and its client
//   GET  /api/info                             joint names, the map, this page's client id
//   GET  /api/skills                           the library's skills
//   GET  /api/events                           the state topic, one server-sent event per sample
//   POST /api/<call>                           stand, stop, reset, damp, clear_stop, release_control,
//                                              execute_skill, track_velocity, navigate (JSON body)
//
// Every POST must come as JSON from the page's own origin; a command, and logout, must carry the
// session's CSRF token in X-CSRF-Token; only an operator commands. Commands and logins are rate
// limited, and each command from a page is logged on stderr ("skillweb audit: ...").

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "client/client.h"
#include "client/web/page_link.h"
#include "client/web/rate_limiter.h"
#include "client/web/sessions.h"
#include "client/web/users_file.h"
#include "client/web/web_server.h"
#include "navigation_map/map2d.h"

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace flsd::web {

struct WebAppOptions {
  std::string page_dir;   // index.html, app.js, style.css
  std::string urdf_path;  // robot/a1/a1.urdf
  std::optional<Map2D> map;
  Client::Options client;      // domain and partition; `security`: the open session's identity
  std::optional<Users> users;  // logins; none: one open session serves every page
  std::string pki_dir;         // with users: DDS Security, each user's DIR/IDENTITY/security.yaml
  std::string agent_program;   // with pki_dir: skillweb itself, run as each page's --page-agent
  SessionLimits sessions;
};

class WebApp {
 public:
  // Throws InputError for a user whose DDS identity does not load.
  explicit WebApp(WebAppOptions options);
  // Ends the streams, then stops serving, then closes the sessions.
  ~WebApp();
  WebApp(const WebApp&) = delete;
  WebApp& operator=(const WebApp&) = delete;

  // Serves on `listen`; returns the port.
  int Listen(const ListenOptions& listen);
  // The open session's client id, or "" with logins.
  std::string open_client_id() const { return open_session_ ? open_session_->link->id() : ""; }

 private:
  void Mount(httplib::Server& server);
  bool Trusted(const httplib::Request& request) const;
  std::shared_ptr<Session> Find(const httplib::Request& request);
  void Login(const httplib::Request& request, httplib::Response& response);
  void Logout(const httplib::Request& request, httplib::Response& response);
  void Events(const std::shared_ptr<Session>& session, httplib::Response& response);
  void Command(const httplib::Request& request, httplib::Response& response);
  std::unique_ptr<PageLink> Connect(const User& user) const;

  WebAppOptions options_;
  std::map<std::string, std::string> identities_;  // each user's security.yaml, with --pki
  std::shared_ptr<Session> open_session_;
  SessionStore sessions_;
  RateLimiter login_attempts_, commands_;
  bool tls_ = false, loopback_ = true;
  std::atomic<bool> stopping_{false};
  std::atomic<int> streams_{0};  // open event streams of all sessions
  std::unique_ptr<WebServer> server_;  // last: it goes first, while the sessions still exist
};

}  // namespace flsd::web
