#pragma once
// A UDP socket for the A1's low-level link: bound to a local address, optionally connected to
// the robot. Receive() waits at most `timeout`, so loops stay on their schedule.

#include <netinet/in.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace flsd::hw {

class UdpSocket {
 public:
  // Binds host:port (port 0: any free port). Throws InputError naming the address on failure.
  UdpSocket(const std::string& host, int port);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  // Sends every datagram from now on to host:port (and accepts only datagrams from there).
  void Connect(const std::string& host, int port);

  bool Send(const uint8_t* data, std::size_t size);
  bool SendTo(const uint8_t* data, std::size_t size, const sockaddr_in& to);

  // Receives one datagram, waiting up to `timeout`; returns its size, or -1 if none came.
  // Datagrams larger than `capacity` are truncated (and then fail the frame's length check).
  int Receive(uint8_t* buffer, std::size_t capacity, std::chrono::microseconds timeout, sockaddr_in* from = nullptr);

  int port() const;

 private:
  int fd_ = -1;
};

sockaddr_in MakeAddress(const std::string& host, int port);

}  // namespace flsd::hw
