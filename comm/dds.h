#pragma once
// A thin RAII layer over Cyclone DDS's C API (Debian packages no C++ binding): entities are
// deleted with their owners, return codes become exceptions naming the call, and QoS is always
// set explicitly on both ends (Cyclone's reader default is best effort, its writer default
// reliable; a silent mismatch is the classic DDS trap).

#include <dds/dds.h>

#include <chrono>
#include <utility>
#include <stdexcept>
#include <string>

#include "comm/security.h"

namespace flsd::dds {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws Error("<what>: <Cyclone's text>") when rc is negative; returns rc otherwise.
dds_return_t Check(dds_return_t rc, const char* what);

// Owns one entity handle; dds_delete also deletes its children (readers of a participant...).
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  Entity(Entity&& other) noexcept : handle_(other.handle_) { other.handle_ = 0; }
  Entity& operator=(Entity&& other) noexcept;
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  ~Entity();

  dds_entity_t get() const { return handle_; }

 private:
  dds_entity_t handle_ = 0;
};

// The QoS of one endpoint. Reliable endpoints keep `depth` samples per instance.
struct EndpointQos {
  bool reliable = true;
  int depth = 1;
  static constexpr EndpointQos Reliable(int depth) { return {true, depth}; }
  static constexpr EndpointQos BestEffort(int depth) { return {false, depth}; }
};

// A participant with one publisher and one subscriber in `partition` (empty: the default
// partition). Several servers and robots share a network by domain id and partition. With
// `security` enabled the participant authenticates and is held to its permissions; creating it
// fails if its own credentials do not validate.
class Domain {
 public:
  Domain(int domain_id, const std::string& partition, const SecurityConfig& security = {});

  dds_entity_t participant() const { return participant_.get(); }
  dds_entity_t publisher() const { return publisher_.get(); }
  dds_entity_t subscriber() const { return subscriber_.get(); }
  int id() const { return domain_id_; }
  bool secured() const { return secured_; }
  // This participant's identity, as WriterIdentity gives it to the peers it writes to.
  std::string identity() const;

 private:
  int domain_id_;
  bool secured_;
  Entity participant_;
  Entity publisher_, subscriber_;
};

dds_entity_t CreateTopic(const Domain& domain, const dds_topic_descriptor_t& type, const char* name);

template <class T>
class Writer {
 public:
  Writer(const Domain& domain, const dds_topic_descriptor_t& type, const char* topic, EndpointQos qos);
  void Write(const T& sample) const { Check(dds_write(writer_.get(), &sample), "dds_write"); }
  dds_entity_t get() const { return writer_.get(); }
  int matched_readers() const;

 private:
  Entity writer_;
};

// Calls a function on Cyclone's receive thread when data arrives: no thread hand-off, so the
// lowest latency, but the function must be quick and must not block.
class DataListener {
 public:
  using Callback = void (*)(dds_entity_t reader, void* arg);
  DataListener(Callback on_data, void* arg);
  ~DataListener() { dds_delete_listener(listener_); }
  DataListener(const DataListener&) = delete;
  DataListener& operator=(const DataListener&) = delete;
  const dds_listener_t* get() const { return listener_; }

 private:
  dds_listener_t* listener_;
};

template <class T>
class Reader {
 public:
  Reader(const Domain& domain, const dds_topic_descriptor_t& type, const char* topic, EndpointQos qos,
         const DataListener* listener = nullptr);

  // Takes up to `max` samples and calls on_sample(const T&, const dds_sample_info_t&) for each
  // one with data. The sample is Cyclone's loan: copy what you keep. Returns the number taken.
  template <class F>
  int Take(F&& on_sample, int max = 32);

  // Blocks until data is available, `guard` fires, or `timeout` passes; true when data is there.
  bool Wait(std::chrono::nanoseconds timeout, dds_entity_t guard = 0);

  dds_entity_t get() const { return reader_.get(); }
  int matched_writers() const;
  // Stops the data listener, waiting for a callback in progress (call before destruction
  // begins, so no callback runs on a half-destroyed owner).
  void RemoveListener() { dds_set_listener(reader_.get(), nullptr); }

 private:
  Entity reader_;
  Entity waitset_;
  Entity readcondition_;
  dds_entity_t attached_guard_ = 0;
};

// Wakes a Reader::Wait from another thread (for shutdown).
class Guard {
 public:
  explicit Guard(const Domain& domain);
  void Trigger() { dds_set_guardcondition(guard_.get(), true); }
  dds_entity_t get() const { return guard_.get(); }

 private:
  Entity guard_;
};

// --- implementation of the templates ---

dds_entity_t CreateEndpoint(const Domain& domain, const dds_topic_descriptor_t& type, const char* topic,
                            EndpointQos qos, bool is_writer, const dds_listener_t* listener = nullptr);
int MatchedCount(dds_entity_t endpoint, bool is_writer);
bool WaitForData(dds_entity_t reader, dds_entity_t waitset, std::chrono::nanoseconds timeout);

template <class T>
Writer<T>::Writer(const Domain& domain, const dds_topic_descriptor_t& type, const char* topic, EndpointQos qos)
    : writer_(CreateEndpoint(domain, type, topic, qos, true)) {}

template <class T>
int Writer<T>::matched_readers() const {
  return MatchedCount(writer_.get(), true);
}

template <class T>
Reader<T>::Reader(const Domain& domain, const dds_topic_descriptor_t& type, const char* topic, EndpointQos qos,
                  const DataListener* listener)
    : reader_(CreateEndpoint(domain, type, topic, qos, false, listener != nullptr ? listener->get() : nullptr)),
      waitset_(Check(dds_create_waitset(domain.participant()), "dds_create_waitset")),
      readcondition_(Check(dds_create_readcondition(reader_.get(), DDS_ANY_STATE), "dds_create_readcondition")) {
  Check(dds_waitset_attach(waitset_.get(), readcondition_.get(), 0), "dds_waitset_attach");
}

// Takes up to `max` samples of type T from `reader` (a handle, as a data listener receives it)
// and calls on_sample(const T&, const dds_sample_info_t&) for each one with data.
template <class T, class F>
int TakeSamples(dds_entity_t reader, F&& on_sample, int max) {
  constexpr int kBatch = 32;
  int total = 0;
  while (total < max) {
    void* samples[kBatch] = {nullptr};
    dds_sample_info_t infos[kBatch];
    const int want = max - total < kBatch ? max - total : kBatch;
    const dds_return_t n = Check(dds_take(reader, samples, infos, want, want), "dds_take");
    struct Loan {  // returned even if on_sample throws
      dds_entity_t reader;
      void** samples;
      dds_return_t n;
      ~Loan() {
        if (n > 0) dds_return_loan(reader, samples, n);
      }
    } loan{reader, samples, n};
    for (int i = 0; i < n; ++i) {
      if (infos[i].valid_data) on_sample(*static_cast<const T*>(samples[i]), infos[i]);
    }
    total += n;
    if (n < want) break;
  }
  return total;
}

template <class T>
template <class F>
int Reader<T>::Take(F&& on_sample, int max) {
  return TakeSamples<T>(reader_.get(), std::forward<F>(on_sample), max);
}

template <class T>
bool Reader<T>::Wait(std::chrono::nanoseconds timeout, dds_entity_t guard) {
  if (guard != attached_guard_) {
    if (attached_guard_ != 0) dds_waitset_detach(waitset_.get(), attached_guard_);
    if (guard != 0) Check(dds_waitset_attach(waitset_.get(), guard, 1), "dds_waitset_attach(guard)");
    attached_guard_ = guard;
  }
  return WaitForData(reader_.get(), waitset_.get(), timeout);
}

template <class T>
int Reader<T>::matched_writers() const {
  return MatchedCount(reader_.get(), false);
}

}  // namespace flsd::dds
