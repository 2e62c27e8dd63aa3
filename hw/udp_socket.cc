#include "hw/udp_socket.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/check.h"

namespace flsd::hw {

sockaddr_in MakeAddress(const std::string& host, int port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  if (port < 0 || port > 65535 || inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1) {
    throw InputError("UDP address " + host + ":" + std::to_string(port) + " is not an IPv4 address and port");
  }
  return address;
}

UdpSocket::UdpSocket(const std::string& host, int port) {
  const sockaddr_in address = MakeAddress(host, port);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw InputError(std::string("cannot create a UDP socket: ") + std::strerror(errno));
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const std::string why = std::strerror(errno);
    close(fd_);
    throw InputError("cannot bind UDP " + host + ":" + std::to_string(port) + ": " + why);
  }
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) close(fd_);
}

void UdpSocket::Connect(const std::string& host, int port) {
  const sockaddr_in address = MakeAddress(host, port);
  if (connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    throw InputError("cannot connect UDP to " + host + ":" + std::to_string(port) + ": " + std::strerror(errno));
  }
}

bool UdpSocket::Send(const uint8_t* data, std::size_t size) {
  return send(fd_, data, size, MSG_DONTWAIT) == static_cast<ssize_t>(size);
}

bool UdpSocket::SendTo(const uint8_t* data, std::size_t size, const sockaddr_in& to) {
  return sendto(fd_, data, size, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&to), sizeof to) ==
         static_cast<ssize_t>(size);
}

int UdpSocket::Receive(uint8_t* buffer, std::size_t capacity, std::chrono::microseconds timeout, sockaddr_in* from) {
  pollfd p{fd_, POLLIN, 0};
  const timespec wait{static_cast<time_t>(timeout.count() / 1000000), static_cast<long>(timeout.count() % 1000000) * 1000};
  if (ppoll(&p, 1, &wait, nullptr) <= 0) return -1;
  socklen_t length = sizeof(sockaddr_in);
  const ssize_t n = recvfrom(fd_, buffer, capacity, MSG_DONTWAIT | MSG_TRUNC, reinterpret_cast<sockaddr*>(from),
                             from != nullptr ? &length : nullptr);
  return n < 0 ? -1 : static_cast<int>(n);
}

int UdpSocket::port() const {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length);
  return ntohs(address.sin_port);
}

}  // namespace flsd::hw
