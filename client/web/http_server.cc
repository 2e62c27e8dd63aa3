#include "client/web/http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace flsd::web {
namespace {

bool SendAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

// Reads the header block and the body its Content-Length announces; false on a malformed,
// oversized or timed-out request.
bool ReadRequest(int fd, HttpRequest& request) {
  std::string data;
  std::size_t head_end = std::string::npos;
  char buffer[4096];
  while (head_end == std::string::npos) {
    if (data.size() > HttpServer::kMaxHeaderBytes) return false;
    const ssize_t n = recv(fd, buffer, sizeof(buffer), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data.append(buffer, static_cast<std::size_t>(n));
    head_end = data.find("\r\n\r\n");
  }
  if (!ParseRequestHead(data.substr(0, head_end), request)) return false;
  std::size_t length = 0;
  const std::string length_text = request.Header("content-length");
  if (!length_text.empty()) {
    if (length_text.find_first_not_of("0123456789") != std::string::npos || length_text.size() > 9) return false;
    length = std::stoul(length_text);
  }
  if (length > HttpServer::kMaxBodyBytes) return false;
  request.body = data.substr(head_end + 4);
  while (request.body.size() < length) {
    const ssize_t n = recv(fd, buffer, sizeof(buffer), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    request.body.append(buffer, static_cast<std::size_t>(n));
  }
  request.body.resize(length);
  return true;
}

std::string Head(int status, const std::string& content_type, const std::string* body) {
  std::ostringstream out;
  out << "HTTP/1.1 " << status << ' ' << StatusText(status) << "\r\nContent-Type: " << content_type
      << "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n";
  if (body) out << "Content-Length: " << body->size() << "\r\n";
  out << "\r\n";
  return out.str();
}

}  // namespace

bool HttpStream::Write(const std::string& bytes) {
  open_ = open_ && running_ && SendAll(fd_, bytes.data(), bytes.size());
  return open_;
}

HttpResponse HttpResponse::Text(int status, std::string body) {
  HttpResponse r;
  r.status = status;
  r.body = std::move(body);
  return r;
}

HttpResponse HttpResponse::Json(int status, std::string body) {
  HttpResponse r;
  r.status = status;
  r.content_type = "application/json";
  r.body = std::move(body);
  return r;
}

const char* StatusText(int status) {
  switch (status) {
    case 200: return "OK";
    case 400: return "Bad Request";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 415: return "Unsupported Media Type";
    case 500: return "Internal Server Error";
    case 503: return "Service Unavailable";
    default: return "Unknown";
  }
}

bool ParseRequestHead(const std::string& head, HttpRequest& request) {
  std::istringstream lines(head);
  std::string line;
  if (!std::getline(lines, line)) return false;
  std::istringstream first(line);
  std::string target, version;
  if (!(first >> request.method >> target >> version) || version.rfind("HTTP/1.", 0) != 0) return false;
  if (target.empty() || target[0] != '/') return false;
  const auto q = target.find('?');
  request.path = target.substr(0, q);
  request.query = q == std::string::npos ? "" : target.substr(q + 1);
  while (std::getline(lines, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) return false;
    request.headers[Lower(Trim(line.substr(0, colon)))] = Trim(line.substr(colon + 1));
  }
  return true;
}

HttpServer::HttpServer(const std::string& host, int port, Handler handler) : handler_(std::move(handler)) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  if (inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1) {
    throw std::runtime_error("not an IPv4 address: " + host);
  }
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int on = 1;
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof(on));
  if (listen_fd_ < 0 || bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      listen(listen_fd_, 16) != 0) {
    const std::string why = std::strerror(errno);
    if (listen_fd_ >= 0) close(listen_fd_);
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " + why);
  }
  socklen_t size = sizeof(address);
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &size);
  port_ = ntohs(address.sin_port);
  acceptor_ = std::thread([this] { Accept(); });
}

HttpServer::~HttpServer() {
  running_ = false;
  shutdown(listen_fd_, SHUT_RDWR);  // wakes accept()
  acceptor_.join();
  close(listen_fd_);
  std::unique_lock<std::mutex> lock(connections_mutex_);
  for (int fd : connections_) shutdown(fd, SHUT_RDWR);  // wakes recv() and send()
  connection_ended_.wait(lock, [this] { return connections_.empty(); });
}

void HttpServer::Accept() {
  while (running_) {
    const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      return;  // shut down
    }
    // A client that stops mid-request must not hold its thread for ever.
    timeval timeout{5, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof(timeout));
    std::lock_guard<std::mutex> lock(connections_mutex_);
    connections_.insert(fd);
    std::thread([this, fd] { Serve(fd); }).detach();
  }
}

void HttpServer::Serve(int fd) {
  HttpRequest request;
  HttpResponse response = ReadRequest(fd, request) ? handler_(request) : HttpResponse::Text(400, "bad request\n");
  if (response.stream) {
    const std::string head = Head(response.status, response.content_type, nullptr);
    HttpStream stream(fd, running_);
    if (stream.Write(head)) response.stream(stream);
  } else {
    const std::string head = Head(response.status, response.content_type, &response.body);
    if (SendAll(fd, head.data(), head.size())) SendAll(fd, response.body.data(), response.body.size());
  }
  shutdown(fd, SHUT_WR);
  std::lock_guard<std::mutex> lock(connections_mutex_);
  close(fd);
  connections_.erase(fd);
  connection_ended_.notify_all();
}

}  // namespace flsd::web
