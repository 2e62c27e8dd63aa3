#pragma once
// The pages skillweb serves, each with a DDS client of its own. A login opens a session: a random
// 256-bit token for its cookie, a CSRF token the page sends with every command, and a PageLink
// made for that user (its own flsd::Client and participant, with the user's DDS Security identity
// when there is one), so that skilld sees each page as a client of its own and the control lease
// belongs to that page. Logout or expiry closes it: its streams end and its client goes, releasing
// the lease. Without logins, one open session stands for every page, as skillweb did before.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "client/web/page_link.h"
#include "client/web/users_file.h"

namespace flsd::web {

struct Session {
  using Clock = std::chrono::steady_clock;

  Session(std::string user, Role role, std::unique_ptr<PageLink> link, Clock::time_point expires);

  const std::string token = RandomToken();  // the cookie's value
  const std::string csrf = RandomToken();
  const std::string user;  // "" for the open session (no logins)
  const Role role;
  const Clock::time_point expires;  // at the latest, however active the page
  const std::unique_ptr<PageLink> link;
  std::atomic<Clock::rep> last_seen;  // Clock ticks: a request or a streamed event
  std::atomic<bool> open{true};
  std::atomic<int> streams{0};

  void Touch(Clock::time_point now = Clock::now()) { last_seen = now.time_since_epoch().count(); }
  // "alice (operator, client ...)": who the audit log and the page name.
  std::string Describe() const;

 private:
  static std::string RandomToken();
};

struct SessionLimits {
  std::chrono::minutes idle{30};     // closed after this long without a request or an open stream
  std::chrono::hours lifetime{12};   // and after this long in any case
  int max_sessions = 16;             // each holds a DDS participant
};

class SessionStore {
 public:
  explicit SessionStore(SessionLimits limits);
  // Closes every session.
  ~SessionStore();
  SessionStore(const SessionStore&) = delete;
  SessionStore& operator=(const SessionStore&) = delete;

  const SessionLimits& limits() const { return limits_; }

  // A new session for `user` with the link `connect` makes; nullptr, and nothing connected, when
  // max_sessions are open or opening. What `connect` throws goes to the caller.
  std::shared_ptr<Session> Open(const User& user, const std::function<std::unique_ptr<PageLink>()>& connect);
  // The open session of `token`, touched; nullptr if there is none or it expired.
  std::shared_ptr<Session> Find(const std::string& token);
  void Close(const std::string& token);

 private:
  void CloseExpired();

  const SessionLimits limits_;
  std::mutex mutex_;
  std::condition_variable stop_;
  bool stopping_ = false;
  int opening_ = 0;  // sessions whose links are being connected, out of the lock
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::thread reaper_;
};

}  // namespace flsd::web
