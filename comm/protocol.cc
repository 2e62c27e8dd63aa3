#include "comm/protocol.h"

namespace flsd::dds {

static_assert(static_cast<int>(Mode::kIdle) == flsd_msgs_MODE_IDLE);
static_assert(static_cast<int>(Mode::kNavigate) == flsd_msgs_MODE_NAVIGATE);
static_assert(static_cast<int>(Mode::kDamp) == flsd_msgs_MODE_DAMP);
static_assert(static_cast<int>(TaskState::kNone) == flsd_msgs_TASK_NONE);
static_assert(static_cast<int>(TaskState::kSafetyStop) == flsd_msgs_TASK_SAFETY_STOP);
static_assert(static_cast<int>(TaskState::kTimeout) == flsd_msgs_TASK_TIMEOUT);
static_assert(static_cast<int>(ReplyStatus::kOk) == flsd_msgs_STATUS_OK);
static_assert(static_cast<int>(ReplyStatus::kInternal) == flsd_msgs_STATUS_INTERNAL);

}  // namespace flsd::dds
