#include "support/warnings.hpp"

#include <cstdio>

namespace fieldlidar::app {

void warn(const std::string& message) {
  std::fflush(stdout);  // keep the order of what was printed before
  std::fprintf(stderr, "fieldlidar: warning: %s\n", message.c_str());
}

void warn_source_losses(const io::FrameSource& source) {
  for (const auto& w : source.warnings()) warn(w);
}

}  // namespace fieldlidar::app
