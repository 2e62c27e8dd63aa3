#pragma once
// A small HTTP/1.1 server on POSIX sockets, enough for skillweb: one thread per connection, one
// request per connection (Connection: close), and responses that are either a whole body or a
// stream the handler writes until the peer goes away (server-sent events). A handful of browsers
// connect at a time, so threads are simpler than an event loop and cost nothing.

#include <atomic>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>

namespace flsd::web {

struct HttpRequest {
  std::string method;  // GET, POST
  std::string path;    // without the query
  std::string query;   // after '?', as sent
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;
  std::string Header(const std::string& name) const {
    const auto it = headers.find(name);
    return it == headers.end() ? "" : it->second;
  }
};

// Writes a streamed response's chunks; false once the peer has gone or the server stops.
class HttpStream {
 public:
  explicit HttpStream(int fd, const std::atomic<bool>& running) : fd_(fd), running_(running) {}
  bool Write(const std::string& bytes);
  bool open() const { return open_ && running_; }

 private:
  int fd_;
  const std::atomic<bool>& running_;
  bool open_ = true;
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
  // Set: the headers go out without a length and this writes the body until it returns.
  std::function<void(HttpStream&)> stream;

  static HttpResponse Text(int status, std::string body);
  static HttpResponse Json(int status, std::string body);
};

class HttpServer {
 public:
  using Handler = std::function<HttpResponse(const HttpRequest&)>;
  static constexpr std::size_t kMaxHeaderBytes = 16 * 1024;
  static constexpr std::size_t kMaxBodyBytes = 64 * 1024;

  // Listens on host:port (port 0: any free one); throws std::runtime_error if it cannot.
  HttpServer(const std::string& host, int port, Handler handler);
  // Stops accepting, ends the open streams and waits for every connection's thread.
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }

 private:
  void Accept();
  void Serve(int fd);

  Handler handler_;
  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> running_{true};
  // Connections run on detached threads; the destructor shuts their sockets and waits for none.
  std::mutex connections_mutex_;
  std::condition_variable connection_ended_;
  std::set<int> connections_;
  std::thread acceptor_;
};

// "Bad Request", "Not Found", ...: the reason phrase of a status code.
const char* StatusText(int status);

// The request line and headers of `head` (up to, not including, the blank line); false if they
// are not HTTP/1.x.
bool ParseRequestHead(const std::string& head, HttpRequest& request);

}  // namespace flsd::web
