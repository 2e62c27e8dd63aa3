#include "client/web/web_app.h"

#include <httplib.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <sstream>

#include "client/web/credentials.h"
#include "client/web/page_agent.h"
#include "client/web/web_json.h"
#include "core/check.h"
#include "robot/a1.h"

namespace flsd::web {
namespace {

using nlohmann::json;

constexpr char kCookie[] = "skillweb_session";
constexpr int kStreamsPerSession = 4;  // a page opens one; reloads may overlap for a moment
// Streams of all sessions together: each holds one of the server's connection threads for as long
// as it is open, so they are kept well below that pool, and calls (a STOP) always find a thread.
constexpr int kStreamsInAll = 24;

// The host part of a Host header ("127.0.0.1:8090" -> "127.0.0.1", "[::1]:8090" -> "[::1]").
std::string HostName(const std::string& host) { return host.substr(0, host.rfind(':')); }

void Reply(httplib::Response& r, int status, const json& body) {
  r.status = status;
  r.set_content(body.dump(), "application/json");
}

void Refuse(httplib::Response& r, int status, const std::string& why) {
  Reply(r, status, json{{"ok", false}, {"status", "refused"}, {"message", why}});
}

std::string CookieValue(const httplib::Request& request, const std::string& name) {
  std::istringstream cookies(request.get_header_value("Cookie"));
  std::string pair;
  while (std::getline(cookies, pair, ';')) {
    const auto begin = pair.find_first_not_of(' ');
    if (begin != std::string::npos && pair.compare(begin, name.size() + 1, name + "=") == 0) {
      return pair.substr(begin + name.size() + 1);
    }
  }
  return "";
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// One line per event on stderr, whole: the audit trail of what each page did.
void AuditLine(const httplib::Request& request, const std::string& who, const std::string& what) {
  std::fprintf(stderr, "skillweb audit: %s from %s: %s: %s\n", UtcNow().c_str(), request.remote_addr.c_str(),
               who.c_str(), what.c_str());
}

// `text` fit for one audit line: no control characters (a forged line), at most 300 of them.
std::string OneLine(std::string text) {
  if (text.size() > 300) text = text.substr(0, 300) + "...";
  for (char& c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return text;
}

json SessionJson(const Session& s, bool logins) {
  const bool op = s.role == Role::kOperator;
  return {{"logged_in", true},
          {"user", s.user},
          {"role", RoleName(s.role)},
          {"logins", logins},
          {"client_id", s.link->id()},
          {"csrf", s.csrf},
          {"can_command", op},
          {"reason", op ? "" : "observer: may watch, not command (log in as an operator to command)"}};
}

std::string ReadFile(const std::string& path, bool& found) {
  std::ifstream in(path, std::ios::binary);
  found = static_cast<bool>(in);
  std::ostringstream bytes;
  if (found) bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace

WebApp::WebApp(WebAppOptions options)
    : options_(std::move(options)),
      sessions_(options_.sessions),
      login_attempts_(5, std::chrono::seconds(10)),           // per remote address
      commands_(20, std::chrono::milliseconds(200)) {         // per session: bursts of 20, 5 a second
  if (!options_.users) {
    open_session_ = std::make_shared<Session>("", Role::kOperator, std::make_unique<LocalPageLink>(options_.client),
                                              Session::Clock::time_point::max());
    return;
  }
  if (options_.pki_dir.empty()) return;
  for (const auto& [name, user] : *options_.users) {
    const std::string where = "--users: user " + name + ": ";
    if (user.identity == "-") throw InputError(where + "with --pki every user needs an identity, not '-'");
    const std::string file = options_.pki_dir + "/" + user.identity + "/security.yaml";
    dds::SecurityConfig security;
    try {
      security = dds::LoadSecurityFile(file);
    } catch (const std::exception& e) {
      throw InputError(where + "identity " + user.identity + ": " + e.what());
    }
    if (!security.enabled) throw InputError(where + file + ": security.enabled is not true");
    identities_[name] = file;
  }
}

WebApp::~WebApp() {
  stopping_ = true;  // streams end within a second
  server_.reset();
}

int WebApp::Listen(const ListenOptions& listen) {
  tls_ = listen.tls();
  loopback_ = IsLoopback(listen.host);
  server_ = std::make_unique<WebServer>(listen, [this](httplib::Server& s) { Mount(s); });
  return server_->port();
}

bool WebApp::Trusted(const httplib::Request& request) const {
  // On loopback, requests must name a loopback host, so that a web site cannot reach skillweb by
  // pointing a domain name of its own at 127.0.0.1.
  const std::string host = request.get_header_value("Host");
  const std::string name = HostName(host);
  if (loopback_ && name != "127.0.0.1" && name != "localhost" && name != "[::1]") return false;
  if (request.method != "POST") return true;
  // A cross-site form cannot send JSON, and a cross-site script would need a CORS preflight,
  // which is never granted; a browser names the origin of every POST.
  const std::string origin = request.get_header_value("Origin");
  return request.get_header_value("Content-Type").rfind("application/json", 0) == 0 &&
         (origin.empty() || origin == (tls_ ? "https://" : "http://") + host);
}

std::shared_ptr<Session> WebApp::Find(const httplib::Request& request) {
  if (open_session_) return open_session_;
  const std::string token = CookieValue(request, kCookie);
  return token.empty() ? nullptr : sessions_.Find(token);
}

void WebApp::Mount(httplib::Server& server) {
  server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (Trusted(req)) return httplib::Server::HandlerResponse::Unhandled;
    Refuse(res, 403, "request from another site or host name");
    return httplib::Server::HandlerResponse::Handled;
  });
  // What went wrong inside stays in skillweb's log: it may name files, hosts or library internals.
  server.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr error) {
    std::string what = "unknown error";
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    std::fprintf(stderr, "skillweb: %s %s failed: %s\n", req.method.c_str(), OneLine(req.path).c_str(),
                 OneLine(what).c_str());
    Refuse(res, 500, "internal error: skillweb's log says more");
  });

  const auto file = [](std::string path, std::string type) {
    return [path = std::move(path), type = std::move(type)](const httplib::Request&, httplib::Response& res) {
      bool found = false;
      const std::string bytes = ReadFile(path, found);
      if (!found) return Refuse(res, 404, "missing " + path);
      res.set_content(bytes, type);
    };
  };
  const std::string page = options_.page_dir;
  server.Get("/", file(page + "/index.html", "text/html; charset=utf-8"));
  server.Get("/index.html", file(page + "/index.html", "text/html; charset=utf-8"));
  server.Get("/app.js", file(page + "/app.js", "text/javascript; charset=utf-8"));
  server.Get("/style.css", file(page + "/style.css", "text/css; charset=utf-8"));
  server.Get("/a1.urdf", file(options_.urdf_path, "application/xml"));

  // The routes below need a session: with logins, the cookie of one.
  const auto with_session = [this](std::function<void(const std::shared_ptr<Session>&, httplib::Response&)> route) {
    return [this, route = std::move(route)](const httplib::Request& req, httplib::Response& res) {
      const std::shared_ptr<Session> session = Find(req);
      if (!session) return Reply(res, 401, json{{"ok", false}, {"status", "login required"}, {"logins", true}});
      route(session, res);
    };
  };
  server.Post("/api/login", [this](const httplib::Request& req, httplib::Response& res) { Login(req, res); });
  server.Post("/api/logout", [this](const httplib::Request& req, httplib::Response& res) { Logout(req, res); });
  // Not logged in is an answer here, not an error: the page shows its login form.
  server.Get("/api/session", [this](const httplib::Request& req, httplib::Response& res) {
    const std::shared_ptr<Session> session = Find(req);
    Reply(res, 200, session ? SessionJson(*session, options_.users.has_value()) : json{{"logged_in", false}, {"logins", true}});
  });
  server.Get("/api/info", with_session([this](const std::shared_ptr<Session>& s, httplib::Response& res) {
               json info{{"client_id", s->link->id()}, {"joint_names", a1::kJointNames}, {"map", nullptr}};
               if (options_.map) info["map"] = ToJson(*options_.map);
               Reply(res, 200, info);
             }));
  server.Get("/api/skills", with_session([](const std::shared_ptr<Session>& s, httplib::Response& res) {
               int status = 200;
               const json skills = s->link->Skills(status);
               Reply(res, status, skills);
             }));
  server.Get("/api/events", with_session([this](const std::shared_ptr<Session>& s, httplib::Response& res) {
               Events(s, res);
             }));
  server.Post(R"(/api/([a-z_]+))", [this](const httplib::Request& req, httplib::Response& res) { Command(req, res); });
}

void WebApp::Login(const httplib::Request& request, httplib::Response& response) {
  if (!options_.users) return Refuse(response, 404, "this skillweb has no logins (no --users): its page is open");
  if (!login_attempts_.Allow(request.remote_addr)) {
    return Refuse(response, 429, "too many login attempts from this address: wait a little");
  }
  std::string name, password;
  try {
    const json body = json::parse(request.body);
    name = body.at("name").get<std::string>();
    password = body.at("password").get<std::string>();
  } catch (const json::exception&) {
    return Refuse(response, 400, "expected {\"name\": ..., \"password\": ...}");
  }
  const auto user = options_.users->find(name);
  // An unknown name costs the same hash as a known one: the answer's time tells nothing.
  static const std::string kNobody = HashPassword("");
  const bool verified = VerifyPassword(password, user == options_.users->end() ? kNobody : user->second.password_hash);
  if (user == options_.users->end() || !verified) {
    AuditLine(request, "login", "refused for user '" + OneLine(name) + "'");
    return Refuse(response, 401, "wrong user name or password");
  }
  std::shared_ptr<Session> session;
  try {
    session = sessions_.Open(user->second, [&] { return Connect(user->second); });
  } catch (const std::exception& e) {
    AuditLine(request, "login", "user '" + OneLine(name) + "': cannot connect its client: " + OneLine(e.what()));
    return Refuse(response, 503, "cannot connect this page to skilld: skillweb's log says why");
  }
  if (!session) return Refuse(response, 503, "too many open sessions: log out elsewhere, or wait for one to expire");
  AuditLine(request, session->Describe(), "logged in");
  const auto lifetime = std::chrono::duration_cast<std::chrono::seconds>(sessions_.limits().lifetime).count();
  response.set_header("Set-Cookie", std::string(kCookie) + "=" + session->token + "; Path=/; Max-Age=" +
                                        std::to_string(lifetime) + "; HttpOnly; SameSite=Strict" +
                                        (tls_ ? "; Secure" : ""));
  Reply(response, 200, SessionJson(*session, true));
}

std::unique_ptr<PageLink> WebApp::Connect(const User& user) const {
  const bool observer = user.role == Role::kObserver;  // its client makes no calls
  const auto identity = identities_.find(user.name);
  if (identity == identities_.end()) {
    Client::Options client = options_.client;
    client.read_only = observer;
    return std::make_unique<LocalPageLink>(client);
  }
  return std::make_unique<AgentPageLink>(AgentOptions{options_.agent_program, options_.client.domain_id,
                                                      options_.client.partition, identity->second, observer});
}

void WebApp::Logout(const httplib::Request& request, httplib::Response& response) {
  const std::shared_ptr<Session> session = Find(request);
  if (!session || session == open_session_) return Refuse(response, 401, "not logged in");
  if (!SameSecret(request.get_header_value("X-CSRF-Token"), session->csrf)) {
    return Refuse(response, 403, "missing or wrong CSRF token (X-CSRF-Token)");
  }
  AuditLine(request, session->Describe(), "logged out");
  sessions_.Close(session->token);
  response.set_header("Set-Cookie", std::string(kCookie) + "=; Path=/; Max-Age=0; HttpOnly; SameSite=Strict" +
                                        (tls_ ? "; Secure" : ""));
  Reply(response, 200, json{{"ok", true}, {"status", "logged out"}});
}

void WebApp::Events(const std::shared_ptr<Session>& session, httplib::Response& response) {
  if (++session->streams > kStreamsPerSession) {
    --session->streams;
    return Refuse(response, 429, "too many open streams for this session");
  }
  if (++streams_ > kStreamsInAll) {
    --streams_;
    --session->streams;
    return Refuse(response, 429, "too many open streams: close other pages");
  }
  auto seen = std::make_shared<uint64_t>(0);
  response.set_chunked_content_provider(
      "text/event-stream",
      [this, session, seen](std::size_t, httplib::DataSink& sink) {
        // The stream's proper end, which the page reads as such (a dead client would otherwise
        // answer at once, and this loop would spin).
        if (stopping_ || !session->open || !session->link->alive()) {
          sink.done();
          return true;
        }
        const std::string event = session->link->NextEvent(*seen, *seen, std::chrono::milliseconds(1000));
        session->Touch();
        // A comment line while no state comes keeps proxies from closing the stream and tells
        // this thread when the page has gone.
        const std::string bytes = event.empty() ? std::string(":\n\n") : event;
        return sink.write(bytes.data(), bytes.size());
      },
      [this, session](bool) {
        --session->streams;
        --streams_;
      });
}

void WebApp::Command(const httplib::Request& request, httplib::Response& response) {
  const std::string name = request.matches[1];
  const std::shared_ptr<Session> session = Find(request);
  if (!session) return Refuse(response, 401, "log in first");
  if (!SameSecret(request.get_header_value("X-CSRF-Token"), session->csrf)) {
    AuditLine(request, session->Describe(), name + " -> refused: missing or wrong CSRF token");
    return Refuse(response, 403, "missing or wrong CSRF token (X-CSRF-Token)");
  }
  // A flood is refused without a line each.
  if (!commands_.Allow(session->token)) return Refuse(response, 429, "too many commands from this page: slow down");
  if (session->role != Role::kOperator) {
    AuditLine(request, session->Describe(), name + " -> refused: an observer does not command");
    return Refuse(response, 403, "observer: may watch, not command");
  }
  int status = 200;
  json reply = session->link->Command(name, request.body, status);
  AuditLine(request, session->Describe(),
            name + " " + OneLine(request.body.empty() ? "{}" : request.body) + " -> " + OneLine(reply["audit"]));
  reply.erase("audit");
  Reply(response, status, reply);
}

}  // namespace flsd::web
