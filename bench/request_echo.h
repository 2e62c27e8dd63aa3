#pragma once
// A peer that answers every call on flsd's request topic at once with an ok reply and no text:
// a request/reply round trip of DDS alone, with flsd's types, QoS and client. `skillctl bench`
// runs one in a process of its own and interleaves its calls with skilld's, call by call, so that
// the ratio of the two shows what skilld's request path adds and nothing else (the same client
// code, the same machine noise within milliseconds).

#include <string>

#include "comm/dds.h"
#include "comm/protocol.h"
#include "flsd_msgs.h"

namespace flsd {

class RequestEcho {
 public:
  RequestEcho(int domain_id, const std::string& partition);
  ~RequestEcho() { requests_.RemoveListener(); }
  RequestEcho(const RequestEcho&) = delete;
  RequestEcho& operator=(const RequestEcho&) = delete;

 private:
  static void OnRequests(dds_entity_t reader, void* self);

  dds::Domain domain_;
  dds::Writer<flsd_msgs_Reply> replies_;
  dds::DataListener listener_;
  dds::Reader<flsd_msgs_Request> requests_;
};

// The partition skillctl bench's echo answers in: next to `partition`, so it never meets skilld's.
std::string EchoPartition(const std::string& partition);

}  // namespace flsd
