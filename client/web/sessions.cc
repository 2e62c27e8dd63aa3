#include "client/web/sessions.h"

#include "client/web/credentials.h"

#include <vector>

namespace flsd::web {

Session::Session(std::string user_name, Role user_role, std::unique_ptr<PageLink> page_link, Clock::time_point end)
    : user(std::move(user_name)), role(user_role), expires(end), link(std::move(page_link)) {
  Touch();
}

std::string Session::RandomToken() { return RandomHex(32); }

std::string Session::Describe() const {
  return (user.empty() ? std::string("open page") : user) + " (" + RoleName(role) + ", client " + link->id() + ")";
}

SessionStore::SessionStore(SessionLimits limits) : limits_(limits) {
  reaper_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_.wait_for(lock, std::chrono::seconds(5), [this] { return stopping_; })) {
      lock.unlock();
      CloseExpired();
      lock.lock();
    }
  });
}

SessionStore::~SessionStore() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    for (auto& [token, session] : sessions_) session->open = false;
  }
  stop_.notify_all();
  reaper_.join();
}

std::shared_ptr<Session> SessionStore::Open(const User& user,
                                            const std::function<std::unique_ptr<PageLink>()>& connect) {
  CloseExpired();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (static_cast<int>(sessions_.size()) + opening_ >= limits_.max_sessions) return nullptr;
    ++opening_;
  }
  // Connecting takes up to seconds (a page agent starts a DDS participant): its place is held
  // meanwhile, so that a login beyond the limit is refused before it makes a client.
  std::shared_ptr<Session> session;
  try {
    std::unique_ptr<PageLink> link = connect();
    const auto expires = Session::Clock::now() + limits_.lifetime;
    session = std::make_shared<Session>(user.name, user.role, std::move(link), expires);
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    --opening_;
    throw;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  --opening_;
  sessions_[session->token] = session;
  return session;
}

std::shared_ptr<Session> SessionStore::Find(const std::string& token) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = sessions_.find(token);
  if (it == sessions_.end()) return nullptr;
  it->second->Touch();
  return it->second;
}

void SessionStore::Close(const std::string& token) {
  std::shared_ptr<Session> closed;  // released out of the lock, as in CloseExpired
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = sessions_.find(token);
  if (it == sessions_.end()) return;
  closed = it->second;
  closed->open = false;
  sessions_.erase(it);
}

void SessionStore::CloseExpired() {
  // Released out of the lock: closing a client releases its lease, a round trip to skilld. A
  // closed session's streams see `open` false and end; the last reference closes the client.
  std::vector<std::shared_ptr<Session>> expired;
  {
    const auto now = Session::Clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = sessions_.begin(); it != sessions_.end();) {
      const Session& s = *it->second;
      const bool idle = s.streams == 0 && now - Session::Clock::time_point(Session::Clock::duration(s.last_seen)) > limits_.idle;
      if (idle || now > s.expires) {
        expired.push_back(it->second);
        it->second->open = false;
        it = sessions_.erase(it);
      } else {
        ++it;
      }
    }
  }
}

}  // namespace flsd::web
