#include "client/types.h"

#include <cmath>

namespace flsd {

std::string Reply::Describe() const {
  if (!answered()) return "no reply from skilld";
  std::string text = std::string(Name(status)) + ": " + message;
  if (!safety_report.empty()) text += " [safety: " + safety_report + "]";
  return text;
}

double StateReport::yaw() const {
  const double w = orientation[0], x = orientation[1], y = orientation[2], z = orientation[3];
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

}  // namespace flsd
