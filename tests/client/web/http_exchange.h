#pragma once
// One HTTP exchange with a server on 127.0.0.1, on a plain socket: what the tests of skillweb send
// its routes without a browser.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <string>

namespace flsd::testutil {

// Sends `request` to 127.0.0.1:port; returns what comes back until the server closes, `stop_at`
// has arrived (a stream never closes), or `timeout` has passed.
inline std::string HttpExchange(int port, const std::string& request, const std::string& stop_at = "",
                                std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  timeval poll{0, 100000};  // recv wakes up to look at the clock
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &poll, sizeof(poll));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string reply;
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0) {
    // A refused request may be cut short by the server: no SIGPIPE, and what came back counts.
    (void)send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    char buffer[4096];
    while ((stop_at.empty() || reply.find(stop_at) == std::string::npos) && std::chrono::steady_clock::now() < until) {
      const ssize_t n = recv(fd, buffer, sizeof(buffer), 0);
      if (n > 0) {
        reply.append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
        break;
      }
    }
  }
  close(fd);
  return reply;
}

}  // namespace flsd::testutil
