#pragma once
// skillweb's HTTP(S) server: cpp-httplib (Debian's libcpp-httplib, built with OpenSSL), listening
// on a thread of its own, and the rule for where it may listen.

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace flsd::web {

struct ListenOptions {
  std::string host = "127.0.0.1";
  int port = 8090;  // 0: any free one
  std::string tls_cert, tls_key;  // both: HTTPS
  bool tls() const { return !tls_cert.empty(); }
};

// Whether `host` is a loopback address (127.0.0.0/8, ::1, localhost).
bool IsLoopback(const std::string& host);

// Why skillweb may not listen on `host`: beyond loopback anyone who reaches the port could watch
// and move the robot, so that needs HTTPS and logins, or the operator's explicit --insecure.
// "" if it may.
std::string ExposureError(const ListenOptions& listen, bool logins, bool insecure);

class WebServer {
 public:
  // Serves the routes `mount` registers; throws InputError naming the flag if the certificate or
  // key do not load or the address cannot be bound.
  WebServer(const ListenOptions& options, const std::function<void(httplib::Server&)>& mount);
  // Stops listening and waits for the connections' threads: whatever streams must end first.
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  int port() const { return port_; }

 private:
  std::unique_ptr<httplib::Server> server_;
  int port_ = 0;
  std::atomic<bool> listen_returned_{false};
  std::thread listener_;
};

}  // namespace flsd::web
