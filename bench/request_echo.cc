#include "bench/request_echo.h"

namespace flsd {

RequestEcho::RequestEcho(int domain_id, const std::string& partition)
    : domain_(domain_id, partition),
      replies_(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos),
      listener_(&RequestEcho::OnRequests, this),
      requests_(domain_, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos, &listener_) {}

void RequestEcho::OnRequests(dds_entity_t reader, void* self) {
  // The writer is built before the reader, so it is there even for a request that comes while
  // the reader's constructor runs; the reader is the callback's, not requests_ (not yet assigned).
  const auto* echo = static_cast<const RequestEcho*>(self);
  static char kEmpty[] = "";
  // Nothing may unwind into Cyclone's receive thread: it would end the process.
  try {
    dds::TakeSamples<flsd_msgs_Request>(reader, [&](const flsd_msgs_Request& request, const dds_sample_info_t&) {
      flsd_msgs_Reply reply{};
      reply.header = request.header;  // the client matches its reply by client id and request id
      reply.status = dds::ToIdl(ReplyStatus::kOk);
      reply.message = kEmpty;
      reply.safety_report = kEmpty;
      echo->replies_.Write(reply);
    }, 1 << 30);
  } catch (...) {
  }
}

std::string EchoPartition(const std::string& partition) { return partition + "-bench-echo"; }

}  // namespace flsd
