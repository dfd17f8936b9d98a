#include "app/stall_detector.hpp"

namespace narwhal {

bool StallDetector::observe(int iteration, Real measure) {
  if (anchor_ < 0.0 || measure < anchor_ / fall_) {
    anchor_ = measure;
    anchor_iteration_ = iteration;
    return false;
  }
  return window_ > 0 && iteration - anchor_iteration_ >= window_;
}

}  // namespace narwhal
