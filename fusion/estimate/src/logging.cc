#include "wearscar/fusion/logging.h"

#include <glog/logging.h>

namespace wearscar::fusion {

void QuietSolverLogging() {
  // Below FATAL nothing is written (and nothing reaches the pre-init
  // stderr fallback either).
  FLAGS_minloglevel = google::GLOG_FATAL;
  FLAGS_stderrthreshold = google::GLOG_FATAL;
}

}  // namespace wearscar::fusion
