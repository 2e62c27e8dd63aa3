#include "comm/dds.h"

#include <memory>

namespace flsd::dds {
namespace {

struct QosDeleter {
  void operator()(dds_qos_t* q) const { dds_delete_qos(q); }
};
using QosPtr = std::unique_ptr<dds_qos_t, QosDeleter>;

}  // namespace

dds_return_t Check(dds_return_t rc, const char* what) {
  if (rc < 0) throw Error(std::string(what) + ": " + dds_strretcode(rc));
  return rc;
}

Entity& Entity::operator=(Entity&& other) noexcept {
  if (this != &other) {
    if (handle_ > 0) dds_delete(handle_);
    handle_ = other.handle_;
    other.handle_ = 0;
  }
  return *this;
}

// Deleting an entity whose parent is already gone returns an error; there is nothing to do then.
Entity::~Entity() {
  if (handle_ > 0) dds_delete(handle_);
}

Domain::Domain(int domain_id, const std::string& partition, const SecurityConfig& security)
    : domain_id_(domain_id), secured_(security.enabled) {
  if (domain_id < 0 || domain_id > 232) {
    throw Error("DDS domain id " + std::to_string(domain_id) + " is outside 0..232");
  }
  QosPtr participant_qos(dds_create_qos());
  SetSecurityQos(participant_qos.get(), security);
  const dds_entity_t participant = dds_create_participant(domain_id, participant_qos.get(), nullptr);
  if (participant < 0 && security.enabled) {
    // Cyclone's plugins print why (an untrusted or expired certificate, a bad signature...).
    throw Error("dds_create_participant: DDS Security refused this participant's credentials (certificate " +
                security.identity_certificate + ", permissions " + security.permissions +
                "); Cyclone's message above says why: " + dds_strretcode(participant));
  }
  participant_ = Entity(Check(participant, "dds_create_participant"));
  QosPtr qos(dds_create_qos());
  if (!partition.empty()) dds_qset_partition1(qos.get(), partition.c_str());
  publisher_ = Entity(Check(dds_create_publisher(participant_.get(), qos.get(), nullptr), "dds_create_publisher"));
  subscriber_ = Entity(Check(dds_create_subscriber(participant_.get(), qos.get(), nullptr), "dds_create_subscriber"));
}

std::string Domain::identity() const {
  dds_guid_t guid;
  Check(dds_get_guid(participant_.get(), &guid), "dds_get_guid");
  return ParticipantIdentity(guid);
}

dds_entity_t CreateTopic(const Domain& domain, const dds_topic_descriptor_t& type, const char* name) {
  // A participant returns the same topic for repeated creation with the same type.
  return Check(dds_create_topic(domain.participant(), &type, name, nullptr, nullptr),
               (std::string("dds_create_topic(") + name + ")").c_str());
}

dds_entity_t CreateEndpoint(const Domain& domain, const dds_topic_descriptor_t& type, const char* topic,
                            EndpointQos endpoint, bool is_writer, const dds_listener_t* listener) {
  const dds_entity_t t = CreateTopic(domain, type, topic);
  QosPtr qos(dds_create_qos());
  dds_qset_reliability(qos.get(), endpoint.reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
                       DDS_MSECS(100));
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, endpoint.depth);
  dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  const std::string what = std::string(is_writer ? "dds_create_writer(" : "dds_create_reader(") + topic + ")";
  return Check(is_writer ? dds_create_writer(domain.publisher(), t, qos.get(), nullptr)
                         : dds_create_reader(domain.subscriber(), t, qos.get(), listener),
               what.c_str());
}

int MatchedCount(dds_entity_t endpoint, bool is_writer) {
  if (is_writer) {
    dds_publication_matched_status_t s;
    Check(dds_get_publication_matched_status(endpoint, &s), "dds_get_publication_matched_status");
    return static_cast<int>(s.current_count);
  }
  dds_subscription_matched_status_t s;
  Check(dds_get_subscription_matched_status(endpoint, &s), "dds_get_subscription_matched_status");
  return static_cast<int>(s.current_count);
}

bool WaitForData(dds_entity_t reader, dds_entity_t waitset, std::chrono::nanoseconds timeout) {
  dds_attach_t triggered[2];
  const dds_return_t n = Check(dds_waitset_wait(waitset, triggered, 2, timeout.count()), "dds_waitset_wait");
  for (int i = 0; i < n; ++i) {
    if (triggered[i] == 0) return true;  // the read condition
  }
  return false;
}

DataListener::DataListener(Callback on_data, void* arg) : listener_(dds_create_listener(arg)) {
  if (listener_ == nullptr) throw Error("dds_create_listener: out of memory");
  dds_lset_data_available(listener_, on_data);
}

Guard::Guard(const Domain& domain)
    : guard_(Check(dds_create_guardcondition(domain.participant()), "dds_create_guardcondition")) {}

}  // namespace flsd::dds
