#include "client/web/web_server.h"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <chrono>

#include "core/check.h"

namespace flsd::web {
namespace {

// Threads for connections. An open page holds one for its event stream all the time, and
// httplib queues, rather than refuses, connections beyond its pool: a page's calls must never
// wait behind the streams (WebApp caps them well below this).
constexpr std::size_t kConnectionThreads = 48;

}  // namespace

bool IsLoopback(const std::string& host) {
  // Numeric addresses only (and "localhost"): a name such as 127.example.org may resolve anywhere.
  if (host == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

std::string ExposureError(const ListenOptions& listen, bool logins, bool insecure) {
  if (IsLoopback(listen.host) || insecure || (listen.tls() && logins)) return "";
  std::string missing;
  if (!listen.tls()) missing = "--tls-cert and --tls-key (HTTPS)";
  if (!logins) missing += std::string(missing.empty() ? "" : " and ") + "--users FILE (a login per page)";
  return "--host " + listen.host + " serves beyond loopback, where anyone who reaches the port could watch and " +
         "move the robot: give " + missing + ", or --insecure to serve it that way regardless";
}

WebServer::WebServer(const ListenOptions& options, const std::function<void(httplib::Server&)>& mount) {
  // OpenSSL writes with write(2), not send(MSG_NOSIGNAL): a page that goes mid-response would
  // otherwise end skillweb with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  if (options.tls_cert.empty() != options.tls_key.empty()) {
    throw InputError("--tls-cert and --tls-key go together: HTTPS needs the certificate and its private key");
  }
  if (options.tls()) {
    for (const std::string* file : {&options.tls_cert, &options.tls_key}) {
      if (access(file->c_str(), R_OK) != 0) {
        throw InputError(std::string(file == &options.tls_cert ? "--tls-cert " : "--tls-key ") + *file + ": cannot read");
      }
    }
    server_ = std::make_unique<httplib::SSLServer>(options.tls_cert.c_str(), options.tls_key.c_str());
    if (!server_->is_valid()) {
      throw InputError("--tls-cert " + options.tls_cert + " and --tls-key " + options.tls_key +
                       ": not a PEM certificate and its matching private key");
    }
  } else {
    server_ = std::make_unique<httplib::Server>();
  }
  server_->new_task_queue = [] { return new httplib::ThreadPool(kConnectionThreads); };
  server_->set_payload_max_length(64 * 1024);
  server_->set_default_headers({{"Cache-Control", "no-store"},
                                {"X-Content-Type-Options", "nosniff"},
                                {"X-Frame-Options", "DENY"},
                                {"Referrer-Policy", "no-referrer"}});
  mount(*server_);
  port_ = options.port == 0 ? server_->bind_to_any_port(options.host)
                            : (server_->bind_to_port(options.host, options.port) ? options.port : -1);
  if (port_ <= 0) {
    throw InputError("cannot listen on --host " + options.host + " --port " + std::to_string(options.port) +
                     " (in use, or not an address of this machine)");
  }
  listener_ = std::thread([this] {
    server_->listen_after_bind();
    listen_returned_ = true;
  });
  // stop() does nothing to a server not yet running: the destructor must not come before it.
  while (!server_->is_running() && !listen_returned_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

WebServer::~WebServer() {
  server_->stop();
  listener_.join();
}

}  // namespace flsd::web
