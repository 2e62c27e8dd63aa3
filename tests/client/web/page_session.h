#pragma once
// One page's exchanges with skillweb, as its browser makes them, over HTTP or HTTPS (cpp-httplib's
// client; skillweb's certificate in the tests is self-signed, so it is not verified): the session
// cookie and CSRF token are kept from the login or the open page's session.

#include <httplib.h>

#include <chrono>
#include <csignal>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

namespace flsd::testutil {

class PageSession {
 public:
  // `url`: skillweb's address as it printed it, "https://127.0.0.1:PORT/".
  explicit PageSession(const std::string& url) : origin_(url.substr(0, url.size() - 1)), http_(origin_) {
    std::signal(SIGPIPE, SIG_IGN);  // OpenSSL writes with write(2): a closed stream must not end the test
    http_.enable_server_certificate_verification(false);
    http_.set_read_timeout(std::chrono::seconds(10));
  }

  // POST /api/login; on success the session's cookie and CSRF token are kept.
  httplib::Result Login(const std::string& name, const std::string& password) {
    const nlohmann::json body{{"name", name}, {"password", password}};
    httplib::Result r = http_.Post("/api/login", Headers(), body.dump(), "application/json");
    if (r && r->status == 200) {
      const std::string set_cookie = r->get_header_value("Set-Cookie");
      cookie_ = set_cookie.substr(0, set_cookie.find(';'));
      csrf_ = nlohmann::json::parse(r->body)["csrf"];
    }
    return r;
  }

  // GET /api/session, keeping its CSRF token (the open page's, without logins).
  httplib::Result Session() {
    httplib::Result r = http_.Get("/api/session", Headers());
    if (r && r->status == 200) csrf_ = nlohmann::json::parse(r->body)["csrf"];
    return r;
  }

  // POST /api/<call> with the session's CSRF token, or `csrf` instead, or from `origin`.
  httplib::Result Command(const std::string& call, const std::string& body = "{}", const std::string* csrf = nullptr,
                          const std::string& origin = "") {
    httplib::Headers headers = Headers();
    headers.emplace("X-CSRF-Token", csrf ? *csrf : csrf_);
    headers.emplace("Origin", origin.empty() ? origin_ : origin);
    return http_.Post(("/api/" + call).c_str(), headers, body, "application/json");
  }

  httplib::Result Get(const std::string& path) { return http_.Get(path.c_str(), Headers()); }

  // The first state event on the page's stream ("data: {...}"), or "" if none comes in `timeout`.
  std::string FirstEvent(std::chrono::seconds timeout) {
    httplib::Client stream(origin_);
    stream.enable_server_certificate_verification(false);
    stream.set_read_timeout(timeout);
    std::string events;
    const auto until = std::chrono::steady_clock::now() + timeout;
    stream.Get("/api/events", Headers(), [&](const char* data, std::size_t size) {
      events.append(data, size);
      return events.find("data: {") == std::string::npos && std::chrono::steady_clock::now() < until;
    });
    const auto at = events.find("data: {");
    return at == std::string::npos ? "" : events.substr(at, events.find("\n\n", at) - at);
  }

  const std::string& csrf() const { return csrf_; }
  const std::string& cookie() const { return cookie_; }

 private:
  httplib::Headers Headers() const {
    httplib::Headers headers;
    if (!cookie_.empty()) headers.emplace("Cookie", cookie_);
    return headers;
  }

  std::string origin_;  // "https://127.0.0.1:PORT"
  httplib::Client http_;
  std::string cookie_, csrf_;
};

}  // namespace flsd::testutil
