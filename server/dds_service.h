#pragma once
// skilld's DDS face: a request thread (take, handle, reply) and a telemetry thread (one state
// sample per control tick). Neither touches the robot; both go through the Controller.

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "comm/dds.h"
#include "server/control_loop.h"
#include "server/request_handler.h"

namespace flsd {

class DdsService {
 public:
  // `controller` and `loop` must outlive the service.
  DdsService(const ServerConfig& config, Controller& controller, const ControlLoop& loop, std::string backend_name);
  ~DdsService() { Stop(); }

  void Start();
  void Stop();

  uint64_t replies_sent() const { return replies_sent_.load(); }

 private:
  void ServeRequests();
  void PublishState();
  void SendReply(const flsd_msgs_Request& request, const ReplyContent& content);

  Controller& controller_;
  const ControlLoop& loop_;
  std::string backend_name_;
  RequestHandler handler_;
  dds::Domain domain_;
  dds::Reader<flsd_msgs_Request> requests_;
  dds::Writer<flsd_msgs_Reply> replies_;
  dds::Writer<flsd_msgs_RobotState> states_;
  dds::Guard wake_;
  std::vector<flsd_msgs_SkillInfo> skills_;

  std::atomic<bool> running_{false};
  std::thread request_thread_, state_thread_;
  std::atomic<uint64_t> replies_sent_{0};
  std::atomic<uint64_t> dropped_{0};
  std::mutex holder_mutex_;
  std::string holder_;  // the lease holder, for telemetry
};

}  // namespace flsd
