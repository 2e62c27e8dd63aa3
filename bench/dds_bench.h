#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "client/client.h"

namespace flsd {

struct DdsBenchOptions {
  double rate_hz = 500;  // calls and ddsperf pings per second: a client streaming at the A1's UDP rate
  int blocks = 5;        // pairs of blocks: skilld's status calls, then ddsperf's pings
  int block_seconds = 2;
  std::string partition = "flsd";  // skilld's; the echo answers next to it (EchoPartition)
  // The client's DDS Security, if on: ddsperf then runs once with it and once without.
  dds::SecurityConfig security;
};

// Round trips of skilld's `status` call through `client` and, in the same run on the same domain
// and Cyclone configuration, Cyclone's own ddsperf ping-pong: what skilld's request path costs on
// top of DDS itself, both at rate_hz. The two alternate in blocks of block_seconds, so that a
// neighbour's load falls on both alike; the ratio reported is the median of the blocks' ratios,
// with their spread. ddsperf reports one-way latency (RTT / 2); it is doubled here. Within skilld's
// blocks every call alternates with one to a RequestEcho (without DDS Security): `ratio_to_echo`
// is skilld's p50 over the echo's, the median of the blocks'. The echo runs as `<this program>
// bench-echo`: only skillctl, which has that hidden command, may call this.
// With security on, ddsperf runs with the client's credentials and then, once more after the
// blocks, without any: that run shows what authentication and encryption add to a round trip.
nlohmann::json RunDdsBenchmark(Client& client, int domain_id, const DdsBenchOptions& options);

}  // namespace flsd
